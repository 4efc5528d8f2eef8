#include "geartopo/core/input_error.hpp"

#include <utility>

namespace geartopo {

std::string located_message(const SourcePosition& where, const std::string& field, const std::string& message) {
  // Built by appending: GCC 12 warns falsely (-Wrestrict) on `"literal" + std::string&&`.
  std::string out = where.file;
  if (where.line > 0) {
    out += ':';
    out += std::to_string(where.line);
    if (where.column > 0) {
      out += ':';
      out += std::to_string(where.column);
    }
  }
  out += ": ";
  if (!field.empty()) {
    out += field;
    out += ": ";
  }
  out += message;
  return out;
}

InputError::InputError(SourcePosition where, std::string field, const std::string& message)
    : std::runtime_error(located_message(where, field, message)), where_(std::move(where)), field_(std::move(field)),
      message_(message) {}

} // namespace geartopo
