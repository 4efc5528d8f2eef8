// geartopo — bad input, located: the one error type of every reader (scene YAML, error tables, topology and traces
// CSV, point clouds, measuring-machine exports). what() is "file:line:column: field: message"; the line (and with
// it the column) is left out when unknown (0), the column alone when only the line is known, the field when empty. Libraries throw it; only the program turns it into exit code 1.
#pragma once

#include <stdexcept>
#include <string>

namespace geartopo {

/// Where a value stands in a text file: 1-based line and character column, 0 when unknown.
struct SourcePosition {
  std::string file;
  int line = 0;
  int column = 0;
};

class InputError : public std::runtime_error {
public:
  InputError(SourcePosition where, std::string field, const std::string& message);
  InputError(std::string file, int line, int column, std::string field, const std::string& message)
      : InputError(SourcePosition{std::move(file), line, column}, std::move(field), message) {}

  const std::string& file() const noexcept { return where_.file; }
  int line() const noexcept { return where_.line; }     ///< 1-based, 0 when unknown
  int column() const noexcept { return where_.column; } ///< 1-based character column, 0 when unknown
  const SourcePosition& where() const noexcept { return where_; }
  /// The offending field: a dotted scene path ("gear.teeth") or a column header; empty when not one field's.
  const std::string& field() const noexcept { return field_; }
  /// The message alone, without the location.
  const std::string& message() const noexcept { return message_; }

private:
  SourcePosition where_;
  std::string field_, message_;
};

/// "file:line:column: field: message", leaving out what is unknown.
std::string located_message(const SourcePosition& where, const std::string& field, const std::string& message);

} // namespace geartopo
