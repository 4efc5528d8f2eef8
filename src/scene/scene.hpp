// geartopo — a scene: one gear on one machine, with wheel, process and measurement grid (docs/scene-format.md).
// Units in the file are named in every key (_mm, _deg, _um); inside, lengths are mm and angles rad.
#pragma once

#include "gears/gear_spec.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace geartopo::scene {

struct Scene {
  std::string source;      ///< file the scene was read from (as given), for messages
  std::string name;        ///< free text
  std::string description; ///< free text
  gears::GearSpec gear;
  /// Gear keys whose values the scene declares assumed (not from a drawing), in file order.
  std::vector<std::string> assumed;
  /// Gear keys that were absent and took their conventional value (tip/root diameter).
  std::vector<std::string> defaulted;
};

/// An input error located in a scene file: what() is "file:line:column: field: message".
class SceneError : public std::runtime_error {
public:
  SceneError(const std::string& file, int line, int column, const std::string& field, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }     ///< 1-based, 0 when unknown
  int column() const { return column_; } ///< 1-based, 0 when unknown
  const std::string& field() const { return field_; }

private:
  std::string file_, field_;
  int line_, column_;
};

/// Reads and validates a scene file, including the gear's domain rules (undercut, pointed tip, …).
/// Throws SceneError.
Scene load_scene(const std::filesystem::path& file);

/// Same from text; `source` names it in messages.
Scene parse_scene(const std::string& text, const std::string& source);

} // namespace geartopo::scene
