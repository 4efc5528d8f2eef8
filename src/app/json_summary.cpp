#include "app/json_summary.hpp"

#include <iostream>

namespace geartopo::app {

namespace {

// A stream buffer that accepts everything and keeps nothing.
class NullBuffer : public std::streambuf {
protected:
  int overflow(int c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

} // namespace

JsonSummary::JsonSummary(bool enabled) {
  if (!enabled) return;
  sink_ = std::make_unique<NullBuffer>();
  saved_ = std::cout.rdbuf(sink_.get());
}

JsonSummary::~JsonSummary() {
  if (saved_ != nullptr) std::cout.rdbuf(saved_);
}

void JsonSummary::emit(const nlohmann::json& summary) {
  if (saved_ == nullptr) return;
  std::cout.rdbuf(saved_);
  saved_ = nullptr;
  std::cout << summary.dump(2) << "\n";
}

} // namespace geartopo::app
