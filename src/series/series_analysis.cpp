// The series analysed: per-gear quantities, their across-series fits, the next gear and the class loss
// (series_analysis.hpp).
#include "geartopo/series/series_analysis.hpp"

#include "geartopo/diagnosis/diagnosis_json.hpp"

#include "geartopo/core/uncertain_value.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

namespace geartopo::series {
namespace {

using evaluation::Quantity;

const char* side_word(int s) { return s == 0 ? "left" : "right"; }

/// The largest of a trace value over the evaluated flanks (nullopt: none).
std::optional<double> worst_of(const evaluation::GearEvaluation& e, const std::function<double(const evaluation::FlankEvaluation&)>& f) {
  std::optional<double> w;
  for (const auto& fl : e.flanks) w = std::max(w.value_or(-1e300), f(fl));
  return w;
}

/// f_p and F_p per flank side and F_r, each when every gear has it (every tooth of that side measured). Their floor:
/// a pitch is the difference of two flanks' positions, each with the probe noise: √2 σ.
void add_pitch_runout(std::vector<SeriesQuantity>& q, const std::vector<GearValues>& gears, double noise) {
  using E = evaluation::GearEvaluation;
  const auto add = [&](std::string key, std::string label, Quantity iso, double floor,
                       const std::function<std::optional<double>(const E&)>& get) {
    SeriesQuantity m;
    m.key = std::move(key), m.label = std::move(label), m.iso = iso, m.floor_um = floor;
    for (const auto& g : gears) {
      const auto v = get(g.iso->evaluation);
      if (!v) return;
      m.values_um.push_back(*v);
    }
    q.push_back(std::move(m));
  };
  for (int s = 0; s < 2; ++s) {
    const auto pitch = [s](const E& e) { return s == 0 ? e.pitch_left : e.pitch_right; };
    add(fmt::format("f_p_{}_um", side_word(s)), fmt::format("f_p, {} flanks", side_word(s)), Quantity::SinglePitch,
        noise * std::sqrt(2.0), [&](const E& e) { const auto p = pitch(e); return p ? std::optional(p->f_p_um) : std::nullopt; });
    add(fmt::format("F_p_{}_um", side_word(s)), fmt::format("F_p, {} flanks", side_word(s)), Quantity::CumulativePitch,
        noise * std::sqrt(2.0), [&](const E& e) { const auto p = pitch(e); return p ? std::optional(p->F_p_um) : std::nullopt; });
  }
  add("F_r_um", "F_r", Quantity::Runout, noise,
      [](const E& e) { return e.runout ? std::optional(e.runout->F_r_um) : std::nullopt; });
}

/// The quantities every gear of the series has, in a fixed order: the residual's mean per side and the tooth thickness, then (when every
/// gear holds traces) f_Hαm, f_Hβm per side and the worst F_α, f_fα, F_β, f_fβ.
std::vector<SeriesQuantity> collect_quantities(const std::vector<GearValues>& gears, const gears::GearSpec& gear) {
  std::vector<SeriesQuantity> q;
  for (int s = 0; s < 2; ++s) {
    SeriesQuantity m;
    m.key = fmt::format("mean_residual_{}_um", side_word(s));
    m.label = fmt::format("mean residual, {} flanks", side_word(s));
    double floor2 = 0.0;
    for (const auto& g : gears) {
      m.values_um.push_back(g.mean_residual_um[s]);
      if (g.points[s]) floor2 = std::max(floor2, g.noise_um * g.noise_um / static_cast<double>(g.points[s]));
    }
    m.floor_um = std::sqrt(floor2);
    q.push_back(std::move(m));
  }
  // A flank moved by δ along its normal moves where it cuts the reference cylinder by δ / cos α_n in the normal
  // section: the normal tooth thickness changes by (δ_L + δ_R) / cos α_n. The model stands at the mean allowance, so
  // the drawing allows ±(A_sne − A_sni)/2 about it.
  SeriesQuantity t;
  t.key = "thickness_deviation_um";
  t.label = "tooth thickness s_n − mean allowance";
  const double cos_an = std::cos(gear.normal_pressure_angle_rad);
  for (size_t k = 0; k < gears.size(); ++k)
    t.values_um.push_back((gears[k].mean_residual_um[0] + gears[k].mean_residual_um[1]) / cos_an);
  t.floor_um = std::hypot(q[0].floor_um, q[1].floor_um) / cos_an;
  const double range_um = 1000.0 * (gear.thickness_allowance_upper_mm - gear.thickness_allowance_lower_mm);
  if (range_um > 0.0) t.limit_um = range_um / 2.0;
  q.push_back(std::move(t));
  const bool all_iso = std::all_of(gears.begin(), gears.end(), [](const GearValues& g) { return g.iso.has_value(); });
  if (!all_iso) return q;
  double noise = 0.0;
  for (const auto& g : gears) noise = std::max(noise, g.noise_um);
  for (int s = 0; s < 2; ++s)
    for (const bool helix : {false, true}) {
      SeriesQuantity m;
      m.key = fmt::format("f_H{}_m_{}_um", helix ? "beta" : "alpha", side_word(s));
      m.label = fmt::format("f_H{}m, {} flanks", helix ? "β" : "α", side_word(s));
      m.iso = helix ? Quantity::HelixSlope : Quantity::ProfileSlope;
      m.floor_um = noise * std::sqrt(12.0 / 30.0); // a slope's scatter over ~30 points of a trace
      for (const auto& g : gears) {
        const auto& side = s == 0 ? g.iso->evaluation.left : g.iso->evaluation.right;
        m.values_um.push_back((helix ? side.f_Hbeta_m_um : side.f_Halpha_m_um).value_or(std::nan("")));
      }
      q.push_back(std::move(m));
    }
  const std::vector<std::tuple<Quantity, const char*, const char*, std::function<double(const evaluation::FlankEvaluation&)>>> worst{
      {Quantity::ProfileTotal, "F_alpha_max_um", "F_α, worst flank", [](const auto& f) { return f.profile.total_um; }},
      {Quantity::ProfileForm, "f_f_alpha_max_um", "f_fα, worst flank", [](const auto& f) { return f.profile.form_um; }},
      {Quantity::HelixTotal, "F_beta_max_um", "F_β, worst flank", [](const auto& f) { return f.helix.total_um; }},
      {Quantity::HelixForm, "f_f_beta_max_um", "f_fβ, worst flank", [](const auto& f) { return f.helix.form_um; }}};
  for (const auto& [iso, key, label, get] : worst) {
    SeriesQuantity m;
    m.key = key, m.label = label, m.iso = iso, m.floor_um = noise;
    for (const auto& g : gears) m.values_um.push_back(worst_of(g.iso->evaluation, get).value_or(std::nan("")));
    q.push_back(std::move(m));
  }
  add_pitch_runout(q, gears, noise);
  return q;
}

std::vector<GearState> states_of(const std::vector<GearValues>& gears) {
  std::vector<GearState> s;
  for (const auto& g : gears)
    s.push_back({(g.gear.start_s + g.mean_grinding_time_s) / 3600.0, g.gear.strokes_since_dressing + g.mean_stroke,
                 g.correction_set});
  return s;
}

void fit_quantity(SeriesQuantity& q, const SeriesResult& r, const SeriesOptions& o) {
  if (r.gears.size() < 3) return;
  for (double v : q.values_um)
    if (!std::isfinite(v)) return;
  q.fit = fit_series(r.states, q.values_um, std::max(q.floor_um, 1e-3));
  q.next = predict(q.fit->chosen, r.next);
  if (!q.limit_um) return;
  q.loss = class_loss(q.fit->chosen, r.next, r.step, *q.limit_um, o.max_gears_ahead);
  // The laws see each gear at its measured points; the shop re-dresses by the strokes and time at a job's start.
  const auto& last = r.gears.back();
  for (auto* s : {&q.loss->strokes_early, &q.loss->strokes_median, &q.loss->strokes_late})
    if (*s) **s -= last.mean_stroke;
  for (auto* t : {&q.loss->time_early_h, &q.loss->time_median_h, &q.loss->time_late_h})
    if (*t) **t -= last.mean_grinding_time_s / 3600.0;
}

} // namespace

bool two_sided_limit(const SeriesQuantity& q) {
  return !q.iso || *q.iso == Quantity::ProfileSlope || *q.iso == Quantity::HelixSlope;
}

double strokes_per_gear(const workbench::Workbench& wb) { return static_cast<double>(wb.setup.path().strokes().size()); }

SeriesResult analyse_series(const SeriesSpec& spec, const workbench::Workbench& wb, const SeriesOptions& options) {
  SeriesResult r;
  r.spec = spec;
  r.strokes_per_gear = strokes_per_gear(wb);
  r.drawing_class = wb.scene.report.tolerance_class;
  std::string corrections_before = spec.gears.empty() ? "" : spec.gears.front().corrections.string();
  int set = 0;
  SeriesOptions per_gear = options;
  per_gear.diagnose_gears = options.diagnose_gears || spec.diagnose_gears;
  for (const auto& g : spec.gears) {
    if (g.corrections.string() != corrections_before) ++set, corrections_before = g.corrections.string();
    r.gears.push_back(gear_values(wb, g, {}, per_gear));
    r.gears.back().correction_set = set;
  }
  r.states = states_of(r.gears);
  const size_t n = r.gears.size();
  const double interval_h = n >= 2 ? (spec.gears.back().start_s - spec.gears.front().start_s) / 3600.0 / (n - 1) : 0.0;
  r.step = {interval_h, r.strokes_per_gear, 0};
  r.next = r.states.back();
  r.next.time_h += interval_h;
  r.next.strokes_since_dressing += r.strokes_per_gear;
  r.quantities = collect_quantities(r.gears, wb.setup.geometry().spec());
  const auto params = workbench::gear_parameters(wb.setup.geometry());
  for (auto& q : r.quantities) {
    if (options.keep_going) options.keep_going();
    if (q.iso && r.drawing_class) q.limit_um = evaluation::tolerance_um(*q.iso, params, *r.drawing_class);
    fit_quantity(q, r, options);
  }
  return r;
}

namespace {

nlohmann::json fit_json(const LawFit& f) {
  nlohmann::json j;
  j["model"] = f.name();
  j["gears"] = f.n;
  j["parameters_count"] = f.p;
  j["scatter_um"] = f.sigma_um;
  j["bic"] = f.bic;
  j["F"] = f.f_statistic;
  j["F_critical"] = f.f_critical;
  j["significant"] = f.significant || f.laws.empty();
  for (const auto& q : f.parameters) {
    nlohmann::json p{{"name", q.name}, {"value", q.value}, {"sigma", q.sigma}, {"determined", q.determined}};
    if (!q.determined) p["why"] = q.why;
    j["parameters"].push_back(p);
  }
  return j;
}

nlohmann::json loss_json(const ClassLoss& c, double limit) {
  nlohmann::json j{{"limit_um", limit}, {"already_outside", c.already}};
  const auto put = [&](const char* k, const auto& v) { j[k] = v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  put("gears_ahead_early", c.gears_early), put("gears_ahead_median", c.gears_median), put("gears_ahead_late", c.gears_late);
  put("strokes_since_dressing_early", c.strokes_early), put("strokes_since_dressing_median", c.strokes_median);
  put("strokes_since_dressing_late", c.strokes_late);
  put("time_h_early", c.time_early_h), put("time_h_median", c.time_median_h), put("time_h_late", c.time_late_h);
  return j;
}

/// A gear's within-job diagnosis in series.json: diagnosis.json's verdict, the chosen explanation (candidate_json; null
/// when none) and what it leaves.
nlohmann::json gear_diagnosis_json(const diagnosis::Diagnosis& d) {
  return {{"verdict", d.verdict},
          {"chosen", d.chosen ? diagnosis::candidate_json(*d.chosen) : nlohmann::json(nullptr)},
          {"withheld", d.withheld.has_value()},
          {"unexplained", d.unexplained},
          {"noise_um", d.noise_um},
          {"rms_before_um", d.rms_before_um},
          {"rms_after_um", d.rms_after_um}};
}

} // namespace

nlohmann::json series_json(const SeriesResult& r) {
  nlohmann::json j;
  j["series"] = r.spec.source;
  j["units"] = "µm, s, h, strokes; deviations plus material positive";
  j["strokes_per_gear"] = r.strokes_per_gear;
  j["drawing_class"] = r.drawing_class ? nlohmann::json(*r.drawing_class) : nlohmann::json(nullptr);
  for (size_t k = 0; k < r.gears.size(); ++k) {
    const auto& g = r.gears[k];
    nlohmann::json e{{"id", g.gear.id}, {"measurement", g.gear.measurement.string()}, {"start_s", g.gear.start_s},
                     {"strokes_since_dressing", g.gear.strokes_since_dressing}, {"dressed_before", g.gear.dressed_before},
                     {"corrections", g.gear.corrections.string()}, {"correction_set", g.correction_set},
                     {"mean_residual_left_um", g.mean_residual_um[0]}, {"mean_residual_right_um", g.mean_residual_um[1]},
                     {"rms_residual_um", g.rms_residual_um}, {"noise_um", g.noise_um},
                     {"time_h", r.states[k].time_h}, {"strokes_at_points", r.states[k].strokes_since_dressing}};
    if (g.iso) {
      const auto& c = g.iso->evaluation.classification;
      e["iso_class"] = c.overall ? nlohmann::json(*c.overall) : nlohmann::json(nullptr);
      const auto& ev = g.iso->evaluation;
      for (const auto& [side, p] : {std::pair{"left", &ev.pitch_left}, std::pair{"right", &ev.pitch_right}})
        if (*p) e[fmt::format("f_p_{}_um", side)] = (*p)->f_p_um, e[fmt::format("F_p_{}_um", side)] = (*p)->F_p_um;
      if (ev.runout) e["F_r_um"] = ev.runout->F_r_um;
    } else e["iso_note"] = g.iso_note;
    if (g.diagnosis) e["diagnosis"] = gear_diagnosis_json(*g.diagnosis);
    j["gears"].push_back(e);
  }
  j["next_gear"] = {{"time_h", r.next.time_h}, {"strokes_since_dressing", r.next.strokes_since_dressing}};
  for (const auto& q : r.quantities) {
    nlohmann::json e{{"key", q.key}, {"label", q.label}, {"values_um", q.values_um}, {"scatter_floor_um", q.floor_um}};
    if (q.fit) {
      e["chosen"] = fit_json(q.fit->chosen);
      for (const auto& t : q.fit->tried) e["tried"].push_back({{"model", t.name()}, {"bic", t.bic}, {"F", t.f_statistic},
                                                               {"significant", t.significant}});
      e["not_testable"] = q.fit->notes;
      e["next_gear"] = {{"median_um", q.next->median_um}, {"lower95_um", q.next->lower95_um},
                        {"upper95_um", q.next->upper95_um}};
    } else e["chosen"] = nullptr;
    if (q.loss) e["class_loss"] = loss_json(*q.loss, *q.limit_um);
    j["quantities"].push_back(e);
  }
  return j;
}

namespace {

std::string parameter_text(const FittedParameter& p) {
  if (!p.determined) return fmt::format("{} not determined ({})", p.name, p.why);
  return fmt::format("{} = {}", p.name, text::with_uncertainty(p.value, p.sigma));
}

std::string loss_text(const SeriesQuantity& q, const SeriesResult& r) {
  const auto& c = *q.loss;
  const std::string limit = q.iso ? fmt::format("class {} (|value| ≤ {:.1f} µm)", *r.drawing_class, *q.limit_um)
                                  : fmt::format("the allowance (±{:.1f} µm)", *q.limit_um);
  if (c.already) return fmt::format("  already outside {} at the next gear\n", limit);
  if (!c.gears_median)
    return c.gears_early ? fmt::format("  {} kept (median) as far as looked; the 95 % interval leaves it {} gears "
                                       "ahead\n", limit, *c.gears_early)
                         : "";
  return fmt::format("  {} expected left {} gears ahead (95 %: {} … {}), at a job starting {:.0f} strokes after "
                     "dressing, {:.2f} h after the series start\n", limit, *c.gears_median, *c.gears_early,
                     c.gears_late ? fmt::format("{}", *c.gears_late) : std::string("beyond"), *c.strokes_median,
                     *c.time_median_h);
}

} // namespace

std::string series_text(const SeriesResult& r) {
  std::string s = fmt::format("{} gears, {} strokes per gear; drawing class {}\n", r.gears.size(), r.strokes_per_gear,
                              r.drawing_class ? std::to_string(*r.drawing_class) : std::string("not given"));
  s += "  gear        start h  strokes  residual L  residual R   RMS µm  class\n";
  for (size_t k = 0; k < r.gears.size(); ++k) {
    const auto& g = r.gears[k];
    const auto& c = g.iso ? g.iso->evaluation.classification.overall : std::optional<int>{};
    s += fmt::format("  {:10} {:8.2f} {:8.0f} {:11.2f} {:11.2f} {:8.2f}  {}\n", g.gear.id, g.gear.start_s / 3600.0,
                     g.gear.strokes_since_dressing, g.mean_residual_um[0], g.mean_residual_um[1], g.rms_residual_um,
                     c ? evaluation::class_label(c) : std::string("–"));
  }
  for (const auto& q : r.quantities) {
    if (!q.fit) continue;
    const auto& f = q.fit->chosen;
    s += fmt::format("{}: {} (scatter {:.2f} µm); next gear {:.2f} µm, 95 % [{:.2f}, {:.2f}]\n", q.label, f.name(),
                     f.sigma_um, q.next->median_um, q.next->lower95_um, q.next->upper95_um);
    if (!f.laws.empty())
      for (const auto& p : f.parameters) s += "  " + parameter_text(p) + "\n";
    if (q.loss) s += loss_text(q, r);
  }
  return s;
}

} // namespace geartopo::series
