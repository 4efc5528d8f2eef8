#include "geartopo/report/prediction_report.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/files/input_file.hpp"
#include "geartopo/core/text_field.hpp"
#include "geartopo/evaluation/tolerances.hpp"
#include "geartopo/render/charts.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <map>
#include <stdexcept>
#include <tuple>

namespace geartopo::report {
namespace {

bool is_class(const std::string& name) { return name.size() > 6 && name.substr(name.size() - 6) == "_class"; }

std::string stem(const std::string& name) {
  const auto us = name.rfind('_');
  return us == std::string::npos ? name : name.substr(0, us);
}

std::string class_text(double v) { return evaluation::class_label(static_cast<int>(std::lround(v))); }

} // namespace

std::string quantity_label(const std::string& name) {
  static const std::map<std::string, std::string> symbols = {
      {"f_p", "f_p"},         {"F_p", "F_p"},         {"f_Halpha", "f_Hα"}, {"f_falpha", "f_fα"},
      {"F_alpha", "F_α"},     {"f_Hbeta", "f_Hβ"},    {"f_fbeta", "f_fβ"},  {"F_beta", "F_β"},
      {"F_r", "F_r"},         {"overall", "overall"}, {"largest_abs", "largest |deviation|"},
      {"thickness", "thickness"}, {"rotation", "rigid rotation"}};
  const auto it = symbols.find(stem(name));
  const std::string s = it == symbols.end() ? stem(name) : it->second;
  return is_class(name) ? "class " + s : s;
}

std::string band_text(const std::string& name, const pipeline::Band& b) {
  if (is_class(name)) return fmt::format("{} [{}, {}]", class_text(b.median), class_text(b.low), class_text(b.high));
  return fmt::format("{:.2f} µm [{:.2f}, {:.2f}]", b.median, b.low, b.high);
}

std::string source_label(const std::string& source) {
  if (source == "map_uncertainty") return "the map's uncertainty";
  if (source == "repeatability") return "the repeatability";
  if (source == "resolution_rounding") return "the rounding to machine.resolution";
  if (source == "effect_uncertainty") return "the effects' uncertainty";
  if (source == "probe_noise") return "the probe noise";
  return source;
}

std::string sampling_line(const pipeline::MonteCarloSummary& s) {
  const auto& r = s.sampling;
  const std::string check = fmt::format("{} exact samples within {:.2g} µm in every µm quantity (threshold {} µm), {:.2g} µm "
                                        "at every point",
                                        r.checked_samples, r.largest_quantity_difference_um, pipeline::kLinearAgreementUm,
                                        r.largest_point_difference_um);
  if (r.method == "linear" && r.reason == "checked") return fmt::format("samples: linear (first order, checked: {})", check);
  if (r.method == "linear") return "samples: linear (first order, not checked)";
  if (r.reason == "check failed") return fmt::format("samples: exact (first order failed its check: {})", check);
  if (r.reason == "forced") return "samples: exact (asked for)";
  return "samples: exact";
}

std::string limit_line(const pipeline::MonteCarloSummary& s) {
  const auto limit = pipeline::after_limit(s);
  if (!limit.measured) return {};
  std::vector<std::string> parts;
  for (const auto& w : limit.without)
    parts.push_back(fmt::format("without {} {} ({} {:.2f} µm)", source_label(w.source), class_text(w.overall_class),
                                quantity_label(limit.limiting_quantity), w.limiting_median_um));
  return fmt::format("limit after compensation: {} (median class {}, {} {:.2f} µm; {})", source_label(limit.dominant),
                     class_text(limit.overall_class), quantity_label(limit.limiting_quantity), limit.limiting_median_um,
                     fmt::join(parts, ", "));
}

std::vector<std::string> prediction_lines(const pipeline::MonteCarloSummary& s) {
  std::vector<std::string> out;
  out.push_back(fmt::format("Predicted gear, median [95 % interval] of {} Monte Carlo samples (seed {}): the machine drawn "
                            "within the scene's uncertainties, corrections from the nominal model",
                            s.samples, s.seed));
  if (s.probe_noise_um > 0.0)
    out.back() += fmt::format("; each gear measured with probe noise σ {} µm", s.probe_noise_um);
  out.push_back(fmt::format("  {:<22} {:>28} {:>28}", "", "before", "after"));
  for (size_t i = 0; i < s.names.size(); ++i)
    out.push_back(fmt::format("  {:<22} {:>28} {:>28}", quantity_label(s.names[i]), band_text(s.names[i], s.before[i]),
                              band_text(s.names[i], s.after[i])));
  out.push_back("  " + sampling_line(s));
  if (const auto limit = limit_line(s); !limit.empty()) out.push_back("  " + limit);
  return out;
}

nlohmann::json prediction_json(const pipeline::MonteCarloSummary& s) {
  nlohmann::json j;
  j["samples"] = s.samples;
  j["seed"] = s.seed;
  j["coverage_probability"] = 0.95;
  j["interval"] = "probabilistically symmetric (JCGM 101:2008 7.7); median of the samples";
  j["model"] = "corrections from the nominal scene; the true machine drawn within machine.uncertainty, repeatability per "
               "stroke, corrections as the controller takes them at machine.resolution (its setpoints rounded: "
               "docs/compensation.md, \"Command resolution\"; docs/monte-carlo.md)";
  if (s.iso)
    j["iso_options"] = {{"iso_direction", std::string(evaluation::to_string(s.iso->direction))},
                        {"helix_slope_sign", std::string(evaluation::to_string(s.iso->helix_slope_sign))}};
  j["probe_noise_um"] = s.probe_noise_um;
  if (!s.gear.empty()) j["gear"] = s.gear; // the gear it is of: evaluate --prediction refuses another's
  nlohmann::json q = nlohmann::json::object();
  const auto band = [](const pipeline::Band& b) { return nlohmann::json{{"median", b.median}, {"low", b.low}, {"high", b.high}}; };
  for (size_t i = 0; i < s.names.size(); ++i) q[s.names[i]] = {{"before", band(s.before[i])}, {"after", band(s.after[i])}};
  j["quantities"] = q;
  j["sampling"] = {{"method", s.sampling.method},
                   {"reason", s.sampling.reason},
                   {"checked_samples", s.sampling.checked_samples},
                   {"largest_point_difference_um", s.sampling.largest_point_difference_um},
                   {"largest_quantity_difference_um", s.sampling.largest_quantity_difference_um},
                   {"threshold_um", pipeline::kLinearAgreementUm}};
  if (const auto limit = pipeline::after_limit(s); limit.measured) {
    nlohmann::json without = nlohmann::json::object();
    for (size_t w = 0; w < limit.without.size(); ++w) {
      nlohmann::json bands = nlohmann::json::object();
      for (size_t i = 0; i < s.names.size(); ++i) bands[s.names[i]] = band(s.after_without[w][i]);
      without[limit.without[w].source] = {{"overall_class", limit.without[w].overall_class},
                                          {"limiting_median_um", limit.without[w].limiting_median_um},
                                          {"quantities", bands}};
    }
    j["limit"] = {{"dominant", limit.dominant},
                  {"text", limit_line(s)},
                  {"overall_class_after", limit.overall_class},
                  {"limiting_quantity", limit.limiting_quantity},
                  {"limiting_median_after_um", limit.limiting_median_um},
                  {"without", without}};
  }
  return j;
}

namespace {

// 1-based line and column of byte `at` of `text`.
std::pair<int, int> line_column(const std::string& text, std::size_t at) {
  at = std::min(at, text.size());
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  const auto nl = text.rfind('\n', at == 0 ? 0 : at - 1);
  const std::size_t start = nl == std::string::npos || nl >= at ? 0 : nl + 1;
  return {static_cast<int>(line), static_cast<int>(at - start) + 1};
}

// prediction.json as JSON, each error located and said without the library's text: a syntax error at its line and
// column, a number beyond a double's range (nlohmann's out_of_range.406) at the number, a key given twice in one
// object by its path (the parser would keep the last silently).
nlohmann::json parse_prediction_text(const std::string& text, const std::string& source) {
  struct Frame {
    std::set<std::string> keys;
    std::string last;
  };
  std::vector<Frame> frames;
  const auto path = [&] {
    std::string p;
    for (size_t i = 0; i + 1 < frames.size(); ++i) p += (p.empty() ? "" : ".") + frames[i].last;
    return p;
  };
  const nlohmann::json::parser_callback_t cb = [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    if (event == E::object_start) frames.emplace_back();
    if (event == E::object_end && !frames.empty()) frames.pop_back();
    if (event == E::key && !frames.empty()) {
      const auto key = parsed.get<std::string>();
      if (!frames.back().keys.insert(key).second) {
        const std::string where = path();
        throw InputError(source, 0, 0, where.empty() ? key : where + "." + key,
                         fmt::format("the key '{}' is given twice{}: each key once (which one would count?)", key,
                                     where.empty() ? "" : " in " + where));
      }
      frames.back().last = key;
    }
    return true;
  };
  try {
    return nlohmann::json::parse(text, cb);
  } catch (const nlohmann::json::parse_error& e) {
    const auto [line, column] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    // nlohmann's text after "parse error at line L, column C: ", without its "[json.exception…]" prefix.
    std::string what = e.what();
    if (const auto at = what.find("column"); at != std::string::npos)
      if (const auto colon = what.find(": ", at); colon != std::string::npos) what = what.substr(colon + 2);
    throw InputError(source, line, column, "", fmt::format("not JSON ({}): a prediction.json of geartopo compensate", what));
  } catch (const nlohmann::json::out_of_range& e) {
    // 406: "number overflow parsing '1e400'".
    std::string token;
    const std::string what = e.what();
    if (const auto a = what.find('\''), b = what.rfind('\''); a != std::string::npos && b > a) token = what.substr(a + 1, b - a - 1);
    const auto at = token.empty() ? std::string::npos : text.find(token);
    const auto [line, column] = at == std::string::npos ? std::pair{0, 0} : line_column(text, at);
    throw InputError(source, line, column, "",
                     fmt::format("'{}' is beyond the range of a number (±1.8·10³⁰⁸): a prediction.json holds finite "
                                 "µm values and classes",
                                 text::excerpt(token)));
  } catch (const nlohmann::json::exception&) {
    throw InputError(source, 0, 0, "", "not a JSON file geartopo can read: a prediction.json of geartopo compensate");
  }
}

} // namespace

pipeline::MonteCarloSummary read_prediction_json(const std::filesystem::path& file) {
  const std::string source = file.string();
  const auto fail = [&](const std::string& field, const std::string& message) -> void {
    throw InputError(source, 0, 0, field, message);
  };
  const nlohmann::json j = parse_prediction_text(input::read_input_file(file, input::kMaxSceneBytes, "prediction file"), source);
  if (!j.is_object()) fail("", "not a JSON object: a prediction.json of geartopo compensate");
  const auto number = [&](const nlohmann::json& parent, const std::string& key, const std::string& field) {
    if (!parent.is_object() || !parent.contains(key) || !parent[key].is_number())
      fail(field, "missing or not a number");
    const double v = parent[key].get<double>();
    if (!std::isfinite(v)) fail(field, "not finite");
    return v;
  };
  pipeline::MonteCarloSummary s;
  const double samples = number(j, "samples", "samples");
  // Bounded before the cast (a double beyond long long's range is undefined to convert): the CLI's --samples limit.
  if (samples < 1 || samples > 1e6 || samples != std::floor(samples))
    fail("samples", fmt::format("{} is not a count of samples in [1, 10⁶]", samples));
  s.samples = static_cast<long long>(samples);
  if (j.contains("seed")) {
    if (!j["seed"].is_number_unsigned()) fail("seed", "not a seed: a whole number of 0 … 2⁶⁴ − 1");
    s.seed = j["seed"].get<std::uint64_t>();
  }
  if (j.contains("coverage_probability")) {
    const double p = number(j, "coverage_probability", "coverage_probability");
    if (!(p > 0.0 && p < 1.0)) fail("coverage_probability", fmt::format("{} is not a probability in (0, 1)", p));
  }
  // The gear the prediction is of (pipeline::gear_record): evaluate refuses another gear's prediction.
  if (j.contains("gear")) {
    if (!j["gear"].is_string() || !j["gear"].get<std::string>().starts_with("teeth="))
      fail("gear", "not a gear record geartopo writes ('teeth=… normal_module_mm=…')");
    s.gear = j["gear"].get<std::string>();
  }
  // Written since the ISO options and the probe noise were recorded; older files: not recorded (nullopt), noise 0.
  if (j.contains("iso_options")) {
    const auto& o = j["iso_options"];
    const auto word = [&](const char* key, auto parse) {
      const std::string field = std::string("iso_options.") + key;
      if (!o.is_object() || !o.contains(key) || !o[key].is_string()) fail(field, "missing or not a word");
      const auto parsed = parse(o[key].get<std::string>());
      if (!parsed) fail(field, fmt::format("'{}' is not one of the words geartopo writes", o[key].get<std::string>()));
      return *parsed;
    };
    s.iso = workbench::IsoOptions{word("iso_direction", evaluation::parse_iso_direction),
                                  word("helix_slope_sign", evaluation::parse_helix_slope_sign)};
  }
  if (j.contains("probe_noise_um")) {
    s.probe_noise_um = number(j, "probe_noise_um", "probe_noise_um");
    if (s.probe_noise_um < 0.0 || s.probe_noise_um > 1000.0)
      fail("probe_noise_um", fmt::format("{} is not a σ of 0 … 1000 µm", s.probe_noise_um));
  }
  if (!j.contains("quantities") || !j["quantities"].is_object() || j["quantities"].empty())
    fail("quantities", "missing: the predicted quantities (a prediction.json of geartopo compensate with --samples > 0)");
  for (const auto& [name, q] : j["quantities"].items()) {
    pipeline::Band sides[2];
    const char* side_names[2] = {"before", "after"};
    for (int k = 0; k < 2; ++k) {
      const std::string field = fmt::format("quantities.{}.{}", name, side_names[k]);
      if (!q.is_object() || !q.contains(side_names[k])) fail(field, "missing");
      const auto& b = q[side_names[k]];
      sides[k] = {number(b, "median", field + ".median"), number(b, "low", field + ".low"), number(b, "high", field + ".high")};
      // What a shard's value may be (merge's check): a known quantity, a class of ISO 1328-1, a magnitude ≥ 0, bounded.
      for (const auto& [part, v] : {std::pair{"median", sides[k].median}, {"low", sides[k].low}, {"high", sides[k].high}})
        if (const auto why = pipeline::quantity_value_refusal(name, v))
          fail(why->starts_with("'") ? fmt::format("quantities.{}", name) : field + "." + part, *why);
      if (!(sides[k].low <= sides[k].median && sides[k].median <= sides[k].high))
        fail(field, fmt::format("low {} ≤ median {} ≤ high {} does not hold", sides[k].low, sides[k].median, sides[k].high));
    }
    s.names.push_back(name);
    s.before.push_back(sides[0]);
    s.after.push_back(sides[1]);
  }
  return s;
}

std::vector<PredictionCheck> check_against_prediction(const pipeline::GearQuantities& measured,
                                                      const pipeline::MonteCarloSummary& prediction,
                                                      const std::string& side, bool with_largest) {
  std::vector<PredictionCheck> out;
  for (size_t i = 0; i < measured.names.size(); ++i) {
    const std::string& name = measured.names[i];
    const bool um = name.size() > 3 && name.substr(name.size() - 3) == "_um";
    if (name == "largest_abs_um" ? !with_largest : !um) continue;
    const int k = prediction.find(name);
    if (k < 0) continue;
    const auto& band = (side == "before" ? prediction.before : prediction.after)[static_cast<size_t>(k)];
    const double v = measured.values[i];
    out.push_back({name, v, band, band.low <= v && v <= band.high});
  }
  return out;
}

std::vector<std::string> prediction_check_lines(const std::vector<PredictionCheck>& checks,
                                                const pipeline::MonteCarloSummary& prediction, const std::string& side) {
  std::vector<std::string> lines;
  lines.push_back(fmt::format("{:<20} {:>10}   predicted {} ({} samples): median [95 % interval]", "", "measured",
                              side == "before" ? "before compensation" : "after compensation", prediction.samples));
  size_t inside = 0;
  for (const auto& c : checks) {
    inside += c.inside ? 1 : 0;
    lines.push_back(fmt::format("{:<20} {:>7.2f} µm   {:<26} {}", quantity_label(c.name), c.measured_um,
                                band_text(c.name, c.band),
                                c.inside ? "inside" : c.measured_um < c.band.low ? "outside (below)" : "outside (above)"));
  }
  lines.push_back(fmt::format("{} of {} inside their 95 % intervals", inside, checks.size()));
  return lines;
}

nlohmann::json prediction_check_json(const std::vector<PredictionCheck>& checks,
                                     const pipeline::MonteCarloSummary& prediction, const std::string& side) {
  nlohmann::json q = nlohmann::json::object();
  int inside = 0;
  for (const auto& c : checks) {
    inside += c.inside ? 1 : 0;
    q[c.name] = {{"measured", c.measured_um}, {"median", c.band.median}, {"low", c.band.low}, {"high", c.band.high},
                 {"inside", c.inside}};
  }
  return {{"side", side},
          {"samples", prediction.samples},
          {"coverage_probability", 0.95},
          {"inside", inside},
          {"outside", static_cast<int>(checks.size()) - inside},
          {"quantities", q}};
}

namespace {

/// The chart of prediction.png: per ISO deviation the before median (grey bar) and 95 % interval (grey whisker), the
/// after median (blue ◆) and interval (blue whisker); `positions` gets each drawn quantity's name → x.
render::BarChart prediction_chart(const pipeline::MonteCarloSummary& s, std::map<std::string, double>& positions) {
  render::BarChart c;
  c.title = fmt::format("Predicted ISO 1328-1 deviations, before and after: median and 95 % interval ({} samples)",
                        s.samples);
  c.size = {1400, 700};
  c.x = {"", "", {}, {}};
  c.y = {"deviation, worst flank (slopes: |value|)", "µm", {}, {}};
  render::BarSeries before_bar{"before, median", {}, render::Rgb{200, 200, 200}};
  render::Series before_whisker, after_whisker, after_median;
  before_whisker.name = "before, 95 % interval";
  before_whisker.colour = render::Rgb{90, 90, 90};
  before_whisker.width = 3.0;
  after_whisker.name = "after, 95 % interval";
  after_whisker.colour = render::Rgb{31, 119, 180};
  after_whisker.width = 3.0;
  after_median.name = "after, median";
  after_median.colour = render::Rgb{31, 119, 180};
  after_median.width = 0.0;
  after_median.marker = render::Marker::diamond;
  after_median.marker_size = 11.0;
  const double nan = std::nan("");
  double x = 0.0;
  for (size_t i = 0; i < s.names.size(); ++i) {
    const auto& n = s.names[i];
    if (is_class(n) || (n.front() != 'f' && n.front() != 'F')) continue; // ISO deviations only
    x += 1.0;
    positions[n] = x;
    c.categories.push_back(quantity_label(n));
    before_bar.values.push_back(s.before[i].median);
    // Whiskers: vertical segments, NaN between them; before left of centre, after right.
    for (const auto& [series, band, dx] : {std::tuple{&before_whisker, s.before[i], -0.18}, std::tuple{&after_whisker, s.after[i], 0.18}}) {
      series->x.insert(series->x.end(), {x + dx, x + dx, nan});
      series->y.insert(series->y.end(), {band.low, band.high, nan});
    }
    after_median.x.insert(after_median.x.end(), {x + 0.18, nan}); // markers only: NaN breaks the line
    after_median.y.insert(after_median.y.end(), {s.after[i].median, nan});
  }
  if (c.categories.empty()) throw std::runtime_error("prediction figure: no ISO quantity was evaluated");
  c.bars.push_back(before_bar);
  c.lines = {before_whisker, after_whisker, after_median};
  c.ref_lines.push_back({render::Orientation::horizontal, 0.0, render::colours::black, 1.0, false, ""});
  c.legend = render::LegendPlace::above;
  return c;
}

} // namespace

Figure prediction_figure(const pipeline::MonteCarloSummary& s, const std::filesystem::path& dir) {
  std::map<std::string, double> positions;
  const render::BarChart c = prediction_chart(s, positions);
  render::render_bar_chart(c, dir / "prediction.png");
  return {"prediction.png", "compensation", c.title,
          "Grey bars: median of the uncompensated gear over the samples; grey whiskers its 95 % interval. Blue: the gear "
          "ground with the nominal corrections (median ◆, 95 % interval), on the same µm scale — no magnification. Each "
          "sample draws the machine's error map within the scene's uncertainties and the axes' repeatability per stroke "
          "(docs/monte-carlo.md).",
          c.size.width, c.size.height, std::nullopt, std::nullopt};
}

void prediction_check_figure(const pipeline::MonteCarloSummary& s, const std::vector<PredictionCheck>& before,
                             const std::vector<PredictionCheck>& after, const std::filesystem::path& png) {
  std::map<std::string, double> positions;
  render::BarChart c = prediction_chart(s, positions);
  c.title = fmt::format("Measured gears against the prediction ({} samples): median and 95 % interval", s.samples);
  const double nan = std::nan("");
  // A gear's measured values as markers on its side's whisker: gear 1 (without corrections) on the grey one, gear 2
  // on the blue one.
  for (const auto& [checks, dx, name, colour, marker] :
       {std::tuple{&before, -0.18, "gear 1 (without corrections), measured", render::Rgb{214, 39, 40}, render::Marker::cross},
        std::tuple{&after, 0.18, "gear 2 (with the corrections), measured", render::Rgb{214, 39, 40}, render::Marker::circle}}) {
    render::Series m;
    m.name = name;
    m.colour = colour;
    m.width = 0.0;
    m.marker = marker;
    m.marker_size = 12.0;
    for (const auto& k : *checks) {
      const auto it = positions.find(k.name);
      if (it == positions.end()) continue;
      m.x.insert(m.x.end(), {it->second + dx, nan});
      m.y.insert(m.y.end(), {k.measured_um, nan});
    }
    if (!m.x.empty()) c.lines.push_back(std::move(m));
  }
  render::render_bar_chart(c, png);
}

} // namespace geartopo::report
