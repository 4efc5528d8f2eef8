#include "yaml_reader.hpp"

#include "geartopo/core/text_field.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

namespace geartopo::scene {
namespace {

std::string scalar_of(const YAML::Node& n) { return n.IsScalar() ? n.Scalar() : std::string(); }

// YAML's own spellings of non-finite numbers are refused here: a scene value is always a finite number.
std::optional<double> parse_double(const std::string& s) {
  double v = 0.0;
  if (text::parse_number(s, v) != std::errc()) return std::nullopt;
  return v;
}

std::optional<long long> parse_integer(const std::string& s) {
  long long v = 0;
  if (text::parse_number(s, v) != std::errc()) return std::nullopt;
  return v;
}

using text::excerpt;

std::string kind_of(const YAML::Node& n) {
  switch (n.Type()) {
  case YAML::NodeType::Map: return "a map";
  case YAML::NodeType::Sequence: return "a list";
  case YAML::NodeType::Null: return "empty";
  case YAML::NodeType::Scalar: return fmt::format("'{}'", excerpt(n.Scalar()));
  default: return "undefined";
  }
}

} // namespace

bool Range::contains(double v) const {
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string Range::str() const {
  return fmt::format("{}{}, {}{}", lo_open ? '(' : '[', lo, hi, hi_open ? ')' : ']');
}

void ReadContext::fail(const YAML::Mark& mark, const std::string& field, const std::string& message) const {
  const int line = mark.is_null() ? 0 : mark.line + 1;
  const int column = mark.is_null() ? 0 : mark.column + 1;
  throw InputError(source, line, column, field, message);
}

void ReadContext::fail_field(const std::string& field, const std::string& message) const {
  for (std::string p = field;; ) {
    if (auto it = marks.find(p); it != marks.end()) fail(it->second, field, message);
    const auto dot = p.rfind('.');
    if (dot == std::string::npos) break;
    p.resize(dot);
  }
  fail(YAML::Mark::null_mark(), field, message);
}

MapReader::MapReader(const YAML::Node& node, std::string path, ReadContext& ctx)
    : node_(node), path_(std::move(path)), ctx_(ctx), mark_(node.Mark()) {
  if (!node.IsMap())
    ctx_.fail(mark_, path_.empty() ? "scene" : path_, fmt::format("expected a map of keys, found {}", kind_of(node)));
  std::set<std::string> seen;
  for (const auto& kv : node_) {
    const std::string key = scalar_of(kv.first);
    if (!seen.insert(key).second) ctx_.fail(kv.first.Mark(), field(key), "duplicate key");
  }
  if (!path_.empty()) ctx_.marks.emplace(path_, mark_);
}

bool MapReader::has(const std::string& key) {
  known_.insert(key); // a reader that asks for a key knows it: "unknown key" messages list it
  for (const auto& kv : node_)
    if (scalar_of(kv.first) == key) return true;
  return false;
}

std::vector<std::string> MapReader::keys() const {
  std::vector<std::string> out;
  for (const auto& kv : node_) out.push_back(scalar_of(kv.first));
  return out;
}

YAML::Node MapReader::value(const std::string& key) {
  known_.insert(key);
  for (const auto& kv : node_) {
    if (scalar_of(kv.first) == key) {
      // An alias (`*m`) carries the mark of its anchor, earlier in the file: a message about this key must point
      // here, at the key, not at the line the anchored value came from.
      const bool alias = kv.second.Mark().pos < kv.first.Mark().pos;
      ctx_.marks[field(key)] = kv.second.IsNull() || alias ? kv.first.Mark() : kv.second.Mark();
      return kv.second;
    }
  }
  return YAML::Node(YAML::NodeType::Undefined);
}

namespace {

/// Levenshtein distance of two keys (bytes): the edits a typing slip takes.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

/// A key that is probably `wanted` misspelled: one holds the other (module_mm, normal_module_mm), or a few edits
/// apart (a quarter of the longer, at least 2).
bool looks_like(const std::string& key, const std::string& wanted) {
  if (key.empty()) return false;
  if (wanted.find(key) != std::string::npos || key.find(wanted) != std::string::npos) return true;
  return edit_distance(key, wanted) <= std::max<size_t>(2, std::max(key.size(), wanted.size()) / 4);
}

} // namespace

void MapReader::missing(const std::string& key, const std::string& what) const {
  // A key of this map that no reader asked for and that looks like the missing one is the user's spelling of it: say
  // that first, where it stands, with the keys read here (the unknown-key message it would get once the rest is read).
  for (const auto& kv : node_) {
    const std::string k = scalar_of(kv.first);
    if (known_.count(k) || !looks_like(k, key)) continue;
    std::set<std::string> known = known_;
    known.insert(key);
    ctx_.fail(kv.first.Mark(), field(k),
              fmt::format("unknown key (known here, among others: {}); did you mean {}? It is missing ({})",
                          fmt::join(known, ", "), key, what));
  }
  ctx_.fail(mark_, field(key), "missing (" + what + ")");
}

std::optional<double> MapReader::optional_number(const std::string& key, const Range& range) {
  const YAML::Node n = value(key);
  if (!n.IsDefined()) return std::nullopt;
  const auto& mark = ctx_.marks[field(key)];
  const auto v = n.IsScalar() ? parse_double(n.Scalar()) : std::nullopt;
  if (!v) ctx_.fail(mark, field(key), fmt::format("{} is not a number", kind_of(n)));
  if (!std::isfinite(*v)) ctx_.fail(mark, field(key), fmt::format("{} is not finite", excerpt(n.Scalar())));
  if (!range.contains(*v)) {
    const bool below = range.lo_open ? *v <= range.lo : *v < range.lo;
    ctx_.fail(mark, field(key), fmt::format("{} is outside {}{}", excerpt(n.Scalar()), range.str(),
                                            below && range.below_lo_because != nullptr
                                                ? fmt::format(": {}", range.below_lo_because)
                                                : std::string()));
  }
  return v;
}

double MapReader::number(const std::string& key, const Range& range) {
  if (auto v = optional_number(key, range)) return *v;
  missing(key, "a number in " + range.str());
}

long long MapReader::integer(const std::string& key, long long lo, long long hi) {
  const YAML::Node n = value(key);
  if (!n.IsDefined()) missing(key, fmt::format("a whole number in [{}, {}]", lo, hi));
  const auto& mark = ctx_.marks[field(key)];
  const auto v = n.IsScalar() ? parse_integer(n.Scalar()) : std::nullopt;
  if (!v) ctx_.fail(mark, field(key), fmt::format("{} is not a whole number", kind_of(n)));
  if (*v < lo || *v > hi) ctx_.fail(mark, field(key), fmt::format("{} is outside [{}, {}]", *v, lo, hi));
  return *v;
}

std::optional<std::string> MapReader::optional_text(const std::string& key) {
  const YAML::Node n = value(key);
  if (!n.IsDefined()) return std::nullopt;
  if (!n.IsScalar()) ctx_.fail(ctx_.marks[field(key)], field(key), fmt::format("expected text, found {}", kind_of(n)));
  return n.Scalar();
}

std::string MapReader::text(const std::string& key) {
  if (auto v = optional_text(key)) return *v;
  missing(key, "text");
}

std::optional<std::string> MapReader::optional_choice(const std::string& key, const std::vector<std::string>& choices) {
  auto v = optional_text(key);
  if (!v) return v;
  for (const auto& c : choices)
    if (*v == c) return v;
  ctx_.fail(ctx_.marks[field(key)], field(key), fmt::format("'{}' is not one of: {}", excerpt(*v), fmt::join(choices, ", ")));
}

std::vector<std::string> MapReader::optional_text_list(const std::string& key) {
  const YAML::Node n = value(key);
  std::vector<std::string> out;
  if (!n.IsDefined()) return out;
  if (!n.IsSequence()) ctx_.fail(ctx_.marks[field(key)], field(key), fmt::format("expected a list, found {}", kind_of(n)));
  for (const auto& item : n) {
    if (!item.IsScalar()) ctx_.fail(item.Mark(), field(key), fmt::format("list item {} is not text", kind_of(item)));
    out.push_back(item.Scalar());
  }
  return out;
}

void MapReader::fail_item(const std::string& key, size_t index, const std::string& message) {
  const YAML::Node n = value(key);
  if (n.IsSequence() && index < n.size()) ctx_.fail(n[index].Mark(), field(key), message);
  ctx_.fail_field(field(key), message);
}

MapReader MapReader::map(const std::string& key) {
  const YAML::Node n = value(key);
  if (!n.IsDefined()) missing(key, "a map");
  return MapReader(n, field(key), ctx_);
}

std::optional<MapReader> MapReader::optional_map(const std::string& key) {
  const YAML::Node n = value(key);
  if (!n.IsDefined()) return std::nullopt;
  return MapReader(n, field(key), ctx_);
}

void MapReader::finish() {
  for (const auto& kv : node_) {
    const std::string key = scalar_of(kv.first);
    if (!known_.count(key)) {
      ctx_.fail(kv.first.Mark(), field(key),
                fmt::format("unknown key (known here: {})", fmt::join(known_, ", ")));
    }
  }
}

} // namespace geartopo::scene
