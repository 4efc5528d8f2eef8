// geartopo — strict reading of YAML maps: every value typed and range-checked, every unknown or duplicate key an
// error, every error located at file:line:column with its dotted field path. Internal to the scene library
// (yaml-cpp stays out of public headers).
#pragma once

#include "geartopo/scene/scene.hpp"

#include <yaml-cpp/yaml.h>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace geartopo::scene {

/// An interval for a number: closed or open at each end; printed as "[lo, hi]", "(lo, hi]", …
struct Range {
  double lo, hi;
  bool lo_open = false, hi_open = false;
  /// Why nothing below `lo` is physical, said when a value is below it (e.g. kPositiveLengthMm's reason).
  const char* below_lo_because = nullptr;
  bool contains(double v) const;
  std::string str() const;
};

/// The smallest length a scene gives for a dimension of the gear, the wheel or the probe (module, face width,
/// diameters, relief lengths): 1 µm. geartopo computes deviations in µm, so a dimension below one µm is smaller than
/// the errors it models: a typo or a wrong unit, never a part. A bare "> 0" let 1e-320 through (a denormal face width
/// that makes every helix trace zero long).
inline constexpr double kMinLengthMm = 1e-3;
inline constexpr const char* kMinLengthBecause =
    "below 0.001 mm (1 µm) a dimension is smaller than the µm deviations geartopo computes: no gear, wheel or probe is "
    "that small";
/// A positive length of a part, mm: [kMinLengthMm, hi].
constexpr Range positive_length_mm(double hi) { return Range{kMinLengthMm, hi, false, false, kMinLengthBecause}; }

/// Shared by all readers of one file: its name and where each field was found.
struct ReadContext {
  std::string source;
  std::map<std::string, YAML::Mark> marks; ///< dotted field path → position of its value (or key)

  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& field, const std::string& message) const;
  /// Fails at the mark recorded for `field`, or at its longest recorded prefix.
  [[noreturn]] void fail_field(const std::string& field, const std::string& message) const;
};

/// The one YAML document of `text`: what hangs yaml-cpp refused first (control characters, a ',' starting a
/// document), a syntax error, too deep a nesting or a second document ('---') located at its line; undefined when
/// the text is empty. `what` names the file's kind in messages ("scene", "series file"). Defined in scene.cpp.
YAML::Node load_one_document(const std::string& text, const ReadContext& ctx, std::string_view what);

class MapReader {
public:
  /// `node` must be a map; `path` is its dotted path ("" for the document root).
  MapReader(const YAML::Node& node, std::string path, ReadContext& ctx);

  double number(const std::string& key, const Range& range);
  std::optional<double> optional_number(const std::string& key, const Range& range);
  long long integer(const std::string& key, long long lo, long long hi);
  std::string text(const std::string& key);
  std::optional<std::string> optional_text(const std::string& key);
  std::optional<std::string> optional_choice(const std::string& key, const std::vector<std::string>& choices);
  std::vector<std::string> optional_text_list(const std::string& key);
  /// Fails at item `index` of the list under `key` (read with optional_text_list).
  [[noreturn]] void fail_item(const std::string& key, size_t index, const std::string& message);
  MapReader map(const std::string& key);
  std::optional<MapReader> optional_map(const std::string& key);
  bool has(const std::string& key); ///< also marks the key as known (for unknown-key messages)
  /// The raw node of a key (marked known), for lists of maps; undefined when absent.
  YAML::Node raw(const std::string& key) { return value(key); }
  /// Keys in file order (readers of open-ended maps, e.g. error constants, iterate over them).
  std::vector<std::string> keys() const;

  /// Fails on the first key that no reader asked for.
  void finish();

  std::string field(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const YAML::Mark& mark() const { return mark_; }
  ReadContext& context() { return ctx_; }

private:
  YAML::Node value(const std::string& key); // marks the key as known and records its position
  [[noreturn]] void missing(const std::string& key, const std::string& what) const;

  YAML::Node node_;
  std::string path_;
  ReadContext& ctx_;
  YAML::Mark mark_;
  std::set<std::string> known_;
};

} // namespace geartopo::scene
