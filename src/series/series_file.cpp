// The series file's strict reader (series_file.hpp), on the scene library's YAML map reader.
#include "geartopo/series/series_file.hpp"

#include "geartopo/aqdef/aqdef.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/files/input_file.hpp"

#include "scene/yaml_reader.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <set>

namespace geartopo::series {
namespace {

using scene::MapReader;
using scene::Range;
using scene::ReadContext;

constexpr Range kStartRange{0.0, 1e9}; // s: 30 years
constexpr double kMaxStrokes = 1e7;

/// A text the AQDEF export writes as `key` (name → K0006, machine → K1082, id → K0014), refused at its field when the
/// key cannot hold it (aqdef::text_refusal: its length in the Q-DAS database), before any gear is read.
std::string aqdef_text(const ReadContext& ctx, const std::string& field, const std::string& text, const char* key,
                       const char* what) {
  if (const auto why = aqdef::text_refusal(key, text))
    ctx.fail_field(field, fmt::format("{} (the {}, written as AQDEF {} by --aqdef)", *why, what, key));
  return text;
}

std::filesystem::path resolved(const std::filesystem::path& base_dir, const std::string& p) {
  const std::filesystem::path path(p);
  return path.is_absolute() ? path : base_dir / path;
}

/// One gear's entry; `previous` is the gear before it (nullptr for the first).
SeriesGear read_gear(MapReader& m, const SeriesSpec& spec, const SeriesGear* previous, size_t index,
                     const std::filesystem::path& dir, double strokes_per_gear) {
  SeriesGear g;
  g.line = m.mark().line + 1;
  g.id = aqdef_text(m.context(), m.field("id"), m.optional_text("id").value_or(fmt::format("gear {}", index + 1)),
                    "K0014", "part ident");
  g.measurement = resolved(dir, m.text("measurement"));
  const bool has_s = m.has("start_s"), has_date = m.has("started");
  if (has_s == has_date)
    m.context().fail(m.mark(), m.field("start_s"), "give its job's start once: start_s (s since the series started) or "
                                                   "started (date and time)");
  if (has_s) g.start_s = m.number("start_s", kStartRange);
  else {
    const std::string text = m.text("started");
    g.start_epoch_s = parse_date_time(text);
    if (!g.start_epoch_s)
      m.context().fail_field(m.field("started"), fmt::format("'{}' is not a date and time YYYY-MM-DDTHH:MM:SS", text));
    if (!spec.started_epoch_s)
      m.context().fail_field(m.field("started"), "a date and time needs the series' own 'started' (its zero)");
    g.start_s = static_cast<double>(*g.start_epoch_s - *spec.started_epoch_s);
    if (g.start_s < 0) m.context().fail_field(m.field("started"), "before the series' start ('started')");
  }
  if (spec.started_epoch_s && !g.start_epoch_s) g.start_epoch_s = *spec.started_epoch_s + std::llround(g.start_s);
  if (previous && !(g.start_s > previous->start_s))
    m.context().fail_field(m.field(has_s ? "start_s" : "started"),
                           fmt::format("{} s is not after the previous gear's start ({} s): gears are listed in the "
                                       "order ground", g.start_s, previous->start_s));
  const auto dressed = m.optional_choice("dressed_before", {"true", "false"});
  g.dressed_before = dressed && *dressed == "true";
  if (m.has("strokes_since_dressing")) {
    if (g.dressed_before)
      m.context().fail_field(m.field("strokes_since_dressing"), "give strokes_since_dressing or dressed_before, not both");
    g.strokes_since_dressing = static_cast<double>(m.integer("strokes_since_dressing", 0, static_cast<long long>(kMaxStrokes)));
  } else if (!g.dressed_before && previous) {
    g.strokes_since_dressing = previous->strokes_since_dressing + strokes_per_gear;
  }
  if (const auto c = m.optional_text("corrections")) g.corrections = resolved(dir, *c);
  m.finish();
  return g;
}

} // namespace

std::optional<long long> parse_date_time(const std::string& text) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, s = 0;
  char sep = 0;
  int consumed = 0;
  if (std::sscanf(text.c_str(), "%4d-%2d-%2d%c%2d:%2d:%2d%n", &y, &mo, &d, &sep, &h, &mi, &s, &consumed) != 7 ||
      consumed != static_cast<int>(text.size()) || (sep != 'T' && sep != ' ') || text.size() != 19)
    return std::nullopt;
  using namespace std::chrono;
  const year_month_day ymd{year{y}, month{static_cast<unsigned>(mo)}, day{static_cast<unsigned>(d)}};
  if (!ymd.ok() || h > 23 || mi > 59 || s > 59 || h < 0 || mi < 0 || s < 0) return std::nullopt;
  return sys_days{ymd}.time_since_epoch().count() * 86400LL + h * 3600LL + mi * 60LL + s;
}

SeriesSpec parse_series(const std::string& text, const std::string& source, double strokes_per_gear) {
  ReadContext ctx{source, {}};
  const YAML::Node root = scene::load_one_document(text, ctx, "series file");
  if (!root.IsDefined() || root.IsNull()) ctx.fail(YAML::Mark::null_mark(), "", "empty series file (scene and gears needed)");
  const std::filesystem::path dir = std::filesystem::path(source).parent_path();
  SeriesSpec spec;
  spec.source = source;
  MapReader top(root, "", ctx);
  spec.name = aqdef_text(ctx, "name", top.optional_text("name").value_or(""), "K0006", "batch");
  spec.scene = resolved(dir, top.text("scene"));
  const auto diagnose = top.optional_choice("diagnose_gears", {"true", "false"});
  spec.diagnose_gears = diagnose && *diagnose == "true";
  spec.machine = aqdef_text(ctx, "machine", top.optional_text("machine").value_or(""), "K1082", "machine");
  if (const auto started = top.optional_text("started")) {
    spec.started_epoch_s = parse_date_time(*started);
    if (!spec.started_epoch_s) ctx.fail_field("started", fmt::format("'{}' is not a date and time YYYY-MM-DDTHH:MM:SS", *started));
  }
  const YAML::Node list = top.raw("gears");
  if (!list.IsDefined()) ctx.fail(top.mark(), "gears", "missing: the list of measured gears (- measurement: …)");
  if (!list.IsSequence() || list.size() == 0)
    ctx.fail(list.Mark(), "gears", "expected a list of measured gears (- measurement: …)");
  std::set<std::string> ids;
  for (size_t i = 0; i < list.size(); ++i) {
    MapReader m(list[i], fmt::format("gears[{}]", i), ctx);
    auto g = read_gear(m, spec, spec.gears.empty() ? nullptr : &spec.gears.back(), i, dir, strokes_per_gear);
    if (!ids.insert(g.id).second) ctx.fail(m.mark(), m.field("id"), fmt::format("'{}' is listed twice", g.id));
    spec.dressing_known = spec.dressing_known || g.dressed_before || m.has("strokes_since_dressing");
    spec.gears.push_back(std::move(g));
  }
  top.finish();
  return spec;
}

std::filesystem::path series_scene(const std::filesystem::path& file) {
  const std::string text = input::read_input_file(file, input::kMaxSceneBytes, "series file");
  ReadContext ctx{file.string(), {}};
  const YAML::Node root = scene::load_one_document(text, ctx, "series file");
  if (!root.IsDefined() || !root.IsMap()) ctx.fail(YAML::Mark::null_mark(), "scene", "not a series file (a map with scene and gears)");
  const YAML::Node scene = root["scene"];
  if (!scene.IsDefined() || !scene.IsScalar()) ctx.fail(root.Mark(), "scene", "missing: the scene file of the series");
  return resolved(file.parent_path(), scene.Scalar());
}

bool is_series_file(const std::filesystem::path& file) {
  try {
    const std::string text = input::read_input_file(file, input::kMaxSceneBytes, "series file");
    const YAML::Node root = scene::load_one_document(text, ReadContext{file.string(), {}}, "series file");
    return root.IsMap() && root["gears"].IsDefined() && root["gears"].IsSequence() && root["scene"].IsDefined() &&
           root["scene"].IsScalar();
  } catch (const std::exception&) {
    return false; // not readable as YAML: the scene reader says why
  }
}

SeriesSpec load_series(const std::filesystem::path& file, double strokes_per_gear) {
  return parse_series(input::read_input_file(file, input::kMaxSceneBytes, "series file"), file.string(), strokes_per_gear);
}

} // namespace geartopo::series
