// geartopo — a domain rule broken by one named input field.
// Libraries throw FieldError with the dotted field path of the scene ("gear.teeth"); the scene reader,
// which knows where each field stands in its file, turns it into "file:line:column: field: message".
#pragma once

#include <stdexcept>
#include <string>

namespace geartopo {

class FieldError : public std::runtime_error {
public:
  FieldError(std::string field, const std::string& message)
      : std::runtime_error(message), field_(std::move(field)) {}

  /// Dotted path of the offending field, e.g. "gear.profile_shift".
  const std::string& field() const noexcept { return field_; }

private:
  std::string field_;
};

} // namespace geartopo
