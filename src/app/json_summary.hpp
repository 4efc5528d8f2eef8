// geartopo — `--json` of run, compare, diagnose and compensate: one JSON object on stdout instead of the text.
#pragma once

#include <nlohmann/json.hpp>

#include <memory>
#include <streambuf>

namespace geartopo::app {

/// While it lives, the command's text on stdout is swallowed, and emit() prints one JSON object instead (the same
/// content as the command's main JSON file), so scripts read stdout with a JSON parser. Warnings and errors stay on
/// stderr. Without --json it does nothing.
class JsonSummary {
public:
  explicit JsonSummary(bool enabled);
  ~JsonSummary();
  JsonSummary(const JsonSummary&) = delete;
  JsonSummary& operator=(const JsonSummary&) = delete;
  void emit(const nlohmann::json& summary);

private:
  std::streambuf* saved_ = nullptr;
  std::unique_ptr<std::streambuf> sink_;
};

} // namespace geartopo::app
