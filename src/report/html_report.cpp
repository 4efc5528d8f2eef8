#include "geartopo/report/html_report.hpp"
#include "html_common.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/core/uncertain_value.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/report/iso_report.hpp"
#include "geartopo/report/improvement.hpp"

#include "geartopo/evaluation/crowning.hpp"
#include "geartopo/evaluation/tolerances.hpp"
#include "geartopo/report/gear_report.hpp"
#include "geartopo/diagnosis/hypothesis_rows.hpp"
#include "geartopo/effects/registry.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <map>
#include <fstream>
#include <numbers>

namespace geartopo::report {
namespace {

using geartopo::Flank;

/// The chain's axes by side: "C, A carrying the gear; X, Z, Y the wheel".
std::string axes_of(const machine::KinematicChain& chain) {
  const auto names = [](const std::vector<machine::AxisSpec>& side) {
    std::string s;
    for (const auto& a : side) s += s.empty() ? a.name : fmt::format(", {}", a.name);
    return s;
  };
  return fmt::format("{} carrying the gear; {} the wheel", names(chain.spec().workpiece), names(chain.spec().tool));
}

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
    case '&': o += "&amp;"; break;
    case '<': o += "&lt;"; break;
    case '>': o += "&gt;"; break;
    case '"': o += "&quot;"; break;
    default: o += c;
    }
  }
  return o;
}

std::string figure_html(const Figure& f) {
  return fmt::format("<figure><img src=\"{}\" alt=\"{}\" width=\"{}\" height=\"{}\"><figcaption><b>{}.</b> {}</figcaption></figure>\n",
                     esc(f.file), esc(f.title), f.width, f.height, esc(f.title), esc(f.caption));
}

std::string figures_of(const std::vector<Figure>& figs, const std::string& section) {
  std::string h;
  for (const auto& f : figs)
    if (f.section == section) h += figure_html(f);
  return h;
}

std::string or_dash(const std::string& s) { return s.empty() ? "—" : s; }

/// "+0.15", "−0.71", and "0.00" rather than "−0.00" for a value that rounds to zero.
std::string signed_um(double v) {
  std::string t = fmt::format("{:+.2f}", v);
  if (t == "-0.00" || t == "+0.00") return "0.00";
  return t;
}

// Where ISO 1328-1:2013 does not apply to the gear (evaluation::validity_refusal: m_n, b, β, z or d outside its range),
// a class or tolerance left out is "–" with this mark, and each table or value group is followed by the footnote
// saying why (a bare "–" left the customer guessing, issue 17).
const char* kNotApplicableMark = "<sup>†</sup>";
const std::string kNotApplicableDash = std::string("–") + kNotApplicableMark;

std::string not_applicable_note(const evaluation::GearParameters& p) {
  const auto refusal = evaluation::validity_refusal(p);
  if (!refusal) return "";
  return std::string("<p class=\"note na\">") + kNotApplicableMark +
         " No class or tolerance: ISO 1328-1:2013 does not apply to this gear: " + esc(*refusal) +
         ". The deviations are evaluated all the same.</p>\n";
}

std::string class_cell(evaluation::Quantity q, double v, const evaluation::GearParameters& p) {
  if (evaluation::validity_refusal(p)) return "<td class=cls>" + kNotApplicableDash + "</td>";
  return "<td class=cls>" + evaluation::class_label(evaluation::tolerance_class(q, v, p)) + "</td>";
}

const evaluation::FlankEvaluation* flank_of(const workbench::IsoResult& iso, int tooth, Flank side) {
  for (const auto& fe : iso.evaluation.flanks)
    if (fe.tooth == tooth && fe.side == side) return &fe;
  return nullptr;
}

// Crowning C_α, C_β of every evaluated flank, from the same traces the ISO values come from, of the flank as ground
// (the deviation from the design plus the design): a gear crowned as drawn shows the drawing's C_α, C_β here.
std::map<std::pair<int, Flank>, std::pair<double, double>> crowning_of(const workbench::Workbench& wb,
                                                                      std::vector<grinding::FlankTopology> topo) {
  std::map<std::pair<int, Flank>, std::pair<double, double>> c;
  for (auto& ft : topo)
    for (auto* trace : {&ft.profile, &ft.helix})
      for (auto& p : *trace) p.deviation_um += p.design_um;
  const auto m = workbench::gear_measurement(wb.setup.geometry(), wb.setup.ranges(), topo);
  for (const auto& f : m.flanks) c[{f.tooth, f.side}] = {evaluation::crowning_um(f.profile), evaluation::crowning_um(f.helix)};
  return c;
}

std::string header_block(const workbench::Workbench& wb, const evaluation::IsoConventions& iso, const std::string& date) {
  const auto& rh = wb.scene.report;
  std::string h = "<table class=header>";
  const auto cell = [&](const std::string& k, const std::string& v) { h += "<th>" + esc(k) + "</th><td>" + esc(or_dash(v)) + "</td>"; };
  h += "<tr>";
  cell("part", rh.part.empty() ? wb.scene.name : rh.part);
  cell("drawing", rh.drawing);
  cell("date", date);
  h += "</tr><tr>";
  cell("operator", rh.operator_name);
  cell("measuring machine", rh.measuring_machine);
  cell("probe diameter", rh.probe_diameter_mm ? fmt::format("{:g} mm", *rh.probe_diameter_mm) : "");
  h += "</tr><tr>";
  cell("scene file", wb.scene.source);
  cell("grinding machine", wb.scene.machine.name);
  cell("ISO profile/helix values", iso.direction == evaluation::IsoDirection::Transverse
                                       ? "transverse (normal / cos β_b)"
                                       : "along the flank normal");
  h += "</tr></table>\n";
  return h;
}

// Gear data: the inspection dimensions exactly as `geartopo gear` computes them (gear_json), and the evaluation ranges.
std::string gear_data_block(const workbench::Workbench& wb) {
  const auto& g = wb.setup.geometry();
  const auto& s = g.spec();
  const auto j = gear_json(wb.scene, g);
  const auto& rg = wb.setup.ranges();
  std::vector<std::pair<std::string, std::string>> rows = {
      {"normal module m_n", fmt::format("{:g} mm", s.normal_module_mm)},
      {"number of teeth z", std::to_string(s.teeth)},
      {"normal pressure angle α_n", fmt::format("{:.3f}°", s.normal_pressure_angle_rad * units::kDegPerRad)},
      {"helix angle β", fmt::format("{:.3f}°, {} hand", std::abs(s.helix_angle_rad) * units::kDegPerRad, gears::to_string(s.hand()))},
      {"lead p_z", std::isfinite(g.lead_mm()) ? fmt::format("{:.3f} mm", g.lead_mm()) : "∞ (spur gear)"},
      {"profile shift coefficient x", fmt::format("{:g}", s.profile_shift)},
      {"face width b", fmt::format("{:g} mm", s.face_width_mm)},
      {"reference / base diameter d, d_b", fmt::format("{:.3f} / {:.3f} mm", g.reference_diameter_mm(), g.base_diameter_mm())},
      {"tip / root diameter d_a, d_f", fmt::format("{:.3f} / {:.3f} mm", g.tip_diameter_mm(), g.root_diameter_mm())},
      {fmt::format("base tangent length W_k, k = {}", j["k"].get<int>()),
       fmt::format("{:.4f} mm (allowed {:.4f} … {:.4f} mm)", j["Wk_mm"].get<double>(), j["Wk_lower_mm"].get<double>(),
                   j["Wk_upper_mm"].get<double>())},
      {fmt::format("dimension over balls M_dK, D_M = {:.3f} mm ({})", j["D_M_mm"].get<double>(), j["D_M_source"].get<std::string>()),
       fmt::format("{:.4f} mm (allowed {:.4f} … {:.4f} mm)", j["MdK_mm"].get<double>(), j["MdK_lower_mm"].get<double>(),
                   j["MdK_upper_mm"].get<double>())},
      {"thickness allowances A_sne / A_sni", fmt::format("{:.1f} / {:.1f} µm", j["A_sne_um"].get<double>(), j["A_sni_um"].get<double>())},
      {"profile evaluation range L_α", fmt::format("d = {:.3f} … {:.3f} mm (roll length L_y {:.3f} … {:.3f} mm)",
                                                     g.diameter_at_roll_length(rg.xi_eval_start_mm), g.diameter_at_roll_length(rg.xi_eval_end_mm),
                                                     rg.xi_eval_start_mm, rg.xi_eval_end_mm)},
      {"helix evaluation range L_β", fmt::format("z = {:.2f} … {:.2f} mm from the datum face", rg.z_eval_start_mm, rg.z_eval_end_mm)},
  };
  if (!wb.scene.assumed.empty()) rows.push_back({"assumed (not from a drawing)", fmt::format("{}", fmt::join(wb.scene.assumed, ", "))});
  std::string h = "<table class=data>";
  for (size_t i = 0; i < rows.size(); i += 2) {
    h += "<tr>";
    for (size_t k = i; k < i + 2; ++k)
      h += k < rows.size() ? "<th>" + esc(rows[k].first) + "</th><td>" + esc(rows[k].second) + "</td>" : "<th></th><td></td>";
    h += "</tr>";
  }
  return h + "</table>\n";
}

// Beside each tooth's trace charts: its values and classes, left and right flank.
std::string trace_value_table(const workbench::IsoResult& iso, int tooth, int shown_class,
                              const std::map<std::pair<int, Flank>, std::pair<double, double>>& crown) {
  using Q = evaluation::Quantity;
  const auto& p = iso.parameters;
  const auto* L = flank_of(iso, tooth, Flank::Left);
  const auto* R = flank_of(iso, tooth, Flank::Right);
  const bool classify = !evaluation::validity_refusal(p);
  std::string h = fmt::format("<table class=values><tr><th>tooth {}</th><th>left (µm)</th><th>class</th><th>right (µm)</th>"
                              "<th>class</th><th>{} (µm)</th></tr>",
                              tooth, classify ? fmt::format("tol. class {}", shown_class) : std::string("tolerance"));
  const auto row = [&](Q q, auto pick) {
    const bool slope = q == Q::ProfileSlope || q == Q::HelixSlope;
    h += "<tr><td>" + esc(std::string(evaluation::symbol(q))) + "</td>";
    for (const auto* fe : {L, R})
      h += fe ? "<td>" + (slope ? signed_um(pick(*fe)) : fmt::format("{:.2f}", pick(*fe))) + "</td>" + class_cell(q, pick(*fe), p)
              : "<td>–</td><td>–</td>";
    h += classify ? fmt::format("<td>{:g}</td></tr>", evaluation::tolerance_um(q, p, shown_class))
                  : "<td>" + kNotApplicableDash + "</td></tr>";
  };
  row(Q::ProfileTotal, [](const evaluation::FlankEvaluation& f) { return f.profile.total_um; });
  row(Q::ProfileForm, [](const evaluation::FlankEvaluation& f) { return f.profile.form_um; });
  row(Q::ProfileSlope, [](const evaluation::FlankEvaluation& f) { return f.profile.slope_um; });
  row(Q::HelixTotal, [](const evaluation::FlankEvaluation& f) { return f.helix.total_um; });
  row(Q::HelixForm, [](const evaluation::FlankEvaluation& f) { return f.helix.form_um; });
  row(Q::HelixSlope, [](const evaluation::FlankEvaluation& f) { return f.helix.slope_um; });
  for (bool profile : {true, false}) {
    h += fmt::format("<tr><td>C_{}</td>", profile ? "α" : "β");
    for (Flank side : {Flank::Left, Flank::Right}) {
      const auto it = crown.find({tooth, side});
      h += it == crown.end() ? "<td>–</td><td></td>" : "<td>" + signed_um(profile ? it->second.first : it->second.second) + "</td><td></td>";
    }
    h += "<td></td></tr>";
  }
  return h + "</table>\n" + not_applicable_note(p);
}

// Every evaluated tooth of one flank side, one row: the six ISO values, each with its class, and the crowning. One
// table per side (nine columns) so that each fits the printed A4 width (issue 25: one table of both sides was cut).
std::string flank_table(const workbench::IsoResult& iso, Flank side,
                        const std::map<std::pair<int, Flank>, std::pair<double, double>>& crown) {
  using Q = evaluation::Quantity;
  const auto& p = iso.parameters;
  const bool classify = !evaluation::validity_refusal(p);
  const Q order[] = {Q::ProfileTotal, Q::ProfileForm, Q::ProfileSlope, Q::HelixTotal, Q::HelixForm, Q::HelixSlope};
  std::string h = fmt::format("<table class=flanks><thead><tr><th>tooth</th><th colspan=8>{} flanks (µm, class)</th></tr><tr><th></th>",
                              side == Flank::Left ? "left" : "right");
  for (int k = 0; k < 6; ++k) {
    h += "<th>" + esc(std::string(evaluation::symbol(order[k]))) + "</th>";
    if (k == 2) h += "<th>C_α</th>";
  }
  h += "<th>C_β</th></tr></thead>\n";
  std::map<int, const evaluation::FlankEvaluation*> teeth;
  for (const auto& fe : iso.evaluation.flanks)
    if (fe.side == side) teeth[fe.tooth] = &fe;
  for (const auto& [tooth, fe] : teeth) {
    h += fmt::format("<tr><td>{}</td>", tooth);
    const auto it = crown.find({fe->tooth, fe->side});
    for (int k = 0; k < 6; ++k) {
      const auto& d = k < 3 ? fe->profile : fe->helix;
      const double v = k % 3 == 0 ? d.total_um : k % 3 == 1 ? d.form_um : d.slope_um;
      const std::string value = k % 3 == 2 ? signed_um(v) : fmt::format("{:.2f}", v);
      h += "<td>" + value + " <span class=cls>" +
           (classify ? evaluation::class_label(evaluation::tolerance_class(order[k], v, p)) : kNotApplicableDash) +
           "</span></td>";
      if (k == 2 || k == 5)
        h += it == crown.end() ? "<td>–</td>" : "<td>" + signed_um(k == 2 ? it->second.first : it->second.second) + "</td>";
    }
    h += "</tr>\n";
  }
  return h + "</table>\n" + not_applicable_note(p); // under each side's table: the two may stand apart
}

std::string means_table(const workbench::IsoResult& iso) {
  const auto v = [](const std::optional<double>& x) { return x ? signed_um(*x) : std::string("–"); };
  std::string h = "<table><tr><th>side</th><th>flanks</th><th>f_Hαm (µm)</th><th>f_Hβm (µm)</th></tr>";
  for (const auto* m : {&iso.evaluation.left, &iso.evaluation.right})
    h += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>", evaluation::to_string(m->side), m->flanks,
                     v(m->f_Halpha_m_um), v(m->f_Hbeta_m_um));
  // (the mean slopes are reported, not classified: docs/iso1328.md, "Classification")
  return h + "</table>\n";
}

std::string tolerance_table(const evaluation::GearParameters& p, int shown_class) {
  if (evaluation::validity_refusal(p)) return "";
  using Q = evaluation::Quantity;
  const Q qs[] = {Q::SinglePitch, Q::CumulativePitch, Q::ProfileTotal, Q::ProfileForm, Q::ProfileSlope,
                  Q::HelixTotal,  Q::HelixForm,       Q::HelixSlope,   Q::Runout};
  std::string h = "<div class=scroll><table><tr><th>tolerance (µm)</th>";
  for (Q q : qs) h += "<th>" + esc(std::string(evaluation::symbol(q))) + "T</th>";
  h += "</tr>";
  std::vector<int> classes = {shown_class};
  if (shown_class != 5) classes.push_back(5);
  for (int c : classes) {
    h += fmt::format("<tr><td>class {}</td>", c);
    for (Q q : qs) h += fmt::format("<td>{:g}</td>", evaluation::tolerance_um(q, p, c));
    h += "</tr>";
  }
  return h + "</table></div>\n";
}

/// A class as the page shows it: "–" with the footnote mark when ISO 1328-1 does not apply.
std::string class_text(const std::optional<int>& c, const evaluation::GearParameters& p) {
  return !c && evaluation::validity_refusal(p) ? kNotApplicableDash : evaluation::class_label(c);
}

// The worst value of each ISO quantity before compensation, its class and where it is.
std::string worst_values_table(const workbench::IsoResult& b) {
  std::string h = "<table><thead><tr><th>quantity</th><th>worst (µm)</th><th>class</th><th>where</th></tr></thead>\n";
  for (const auto& q : b.evaluation.classification.quantities)
    h += fmt::format("<tr><td>{}</td><td>{:.2f}</td><td>{}</td><td>{}</td></tr>\n", esc(std::string(evaluation::symbol(q.quantity))),
                     q.worst_value_um, class_text(q.flank_class, b.parameters), esc(q.where));
  h += fmt::format("<tr><th>overall class</th><th colspan=3>{}</th></tr></table>\n",
                   class_text(b.evaluation.classification.overall, b.parameters));
  return h + not_applicable_note(b.parameters);
}

bool is_size_name(const std::string& n) {
  return n.size() > 3 && n.compare(n.size() - 3, 3, "_um") == 0 && n != "thickness_um" && n != "rotation_um";
}

// Classes before → predicted after: every quantity's median [95 % interval] from the prediction, both sides, with its
// class band and the predicted improvement (improvement.hpp). The nominal after-state is not in it.
std::string predicted_table(const pipeline::MonteCarloSummary& p) {
  std::map<std::string, Improvement> gain;
  for (const auto& i : predicted_improvement(p)) gain[i.name] = i;
  // µm in the header, not in every cell: the table fits the printed page.
  const auto band = [&](const std::string& name, bool after) -> std::string {
    const int k = p.find(name);
    if (k < 0) return "–";
    const auto& b = (after ? p.after : p.before)[static_cast<size_t>(k)];
    if (name.size() > 6 && name.compare(name.size() - 6, 6, "_class") == 0) return esc(band_text(name, b));
    return fmt::format("{:.2f} [{:.2f}, {:.2f}]", b.median, b.low, b.high);
  };
  std::string h = "<table class=result><thead><tr><th>quantity</th><th>before (µm)</th><th>class before</th>"
                  "<th>predicted after (µm)</th><th>class after</th><th>improvement (%)</th></tr></thead>\n";
  if (p.find("overall_class") >= 0)
    h += "<tr class=overall><td>overall flank tolerance class</td><td></td><td>" + band("overall_class", false) +
         "</td><td></td><td>" + band("overall_class", true) + "</td><td></td></tr>\n";
  for (const auto& n : p.names) {
    if (!is_size_name(n)) continue;
    const std::string stem = n.substr(0, n.size() - 3);
    const auto g = gain.find(n);
    h += "<tr><td>" + esc(quantity_label(n)) + "</td><td>" + band(n, false) + "</td><td>" + band(stem + "_class", false) +
         "</td><td>" + band(n, true) + "</td><td>" + band(stem + "_class", true) + "</td><td>" +
         (g == gain.end() ? std::string("–") : esc(improvement_number_text(g->second))) + "</td></tr>\n";
  }
  return h + "</table>\n";
}

// Without a prediction (--samples 0): the model's values before, and the nominal after-state labelled as what it is.
std::string nominal_table(const workbench::IsoResult& b, const workbench::IsoResult& a) {
  std::string h = fmt::format("<table class=result><thead><tr><th>quantity</th><th>before (µm)</th><th>class</th>"
                              "<th>{} (µm)</th><th>class</th></tr></thead>\n", kNominalLabel);
  const auto& qb = b.evaluation.classification.quantities;
  const auto& qa = a.evaluation.classification.quantities;
  h += fmt::format("<tr class=overall><td>overall flank tolerance class</td><td></td><td>{}</td><td></td><td>{}</td></tr>\n",
                   class_text(b.evaluation.classification.overall, b.parameters),
                   class_text(a.evaluation.classification.overall, a.parameters));
  const auto um = [](double v) { const std::string t = fmt::format("{:.2f}", v); return t == "-0.00" ? std::string("0.00") : t; };
  for (size_t i = 0; i < qb.size() && i < qa.size(); ++i)
    h += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                     esc(std::string(evaluation::symbol(qb[i].quantity))), um(qb[i].worst_value_um),
                     class_text(qb[i].flank_class, b.parameters), um(qa[i].worst_value_um), class_text(qa[i].flank_class, a.parameters));
  return h + "</table>\n";
}

// The first page (its own sheet in print): what a customer reads in 30 seconds — the gear, the machine, the classes
// before → predicted after, the diagnosis's verdict and one topology picture.
std::string first_page(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const std::vector<Figure>& figs) {
  const auto& s = wb.setup.geometry().spec();
  std::string h = "<section class=first>\n";
  h += fmt::format("<p class=lead><b>Gear</b> m_n {:g} mm, z {}, α_n {:.1f}°, β {:.1f}° {} hand, x {:g}, b {:g} mm. "
                   "<b>Grinding machine</b> {}.</p>\n",
                   s.normal_module_mm, s.teeth, s.normal_pressure_angle_rad * units::kDegPerRad,
                   std::abs(s.helix_angle_rad) * units::kDegPerRad, gears::to_string(s.hand()), s.profile_shift,
                   s.face_width_mm, esc(or_dash(wb.scene.machine.name)));
  if (r.prediction) {
    const auto& p = *r.prediction;
    h += "<h2>ISO 1328-1:2013 classes before → predicted after compensation</h2>\n" + predicted_table(p);
    h += fmt::format("<p class=note>Median [95 % interval] of {} Monte Carlo samples, each a machine drawn within the "
                     "scene's uncertainties grinding the gear before and after the corrections (docs/monte-carlo.md); worst "
                     "flank, slopes as |value|. Improvement: 100 (B − A)/B, B and A the medians before and after; its "
                     "interval: A at the ends of the after-interval.",
                     p.samples);
    // A size predicted worse, in the same paragraph (page 1 keeps room for its figure): the cause measured, and for the
    // command resolution its mechanism in brief (in full on the console, in iso1328.json and docs/compensation.md).
    for (const auto& w : predicted_worsening(p)) {
      std::string text = worsening_text(w);
      if (w.source == "resolution_rounding")
        text = text.substr(0, text.find(" — ")) + " — the held axes' whole command units (docs/compensation.md)";
      h += " <b>Worse after compensation:</b> " + esc(text) + ".";
    }
    h += "</p>\n";
    const int cls = p.find("overall_class");
    if (cls >= 0 && p.after[static_cast<size_t>(cls)].median > p.before[static_cast<size_t>(cls)].median)
      h += "<p class=warn><b>The predicted gear is worse after compensation</b> (overall class, medians): do not apply "
           "these corrections before the cause is found.</p>\n";
  } else {
    h += "<h2>ISO 1328-1:2013 classes</h2>\n" + nominal_table(r.iso_before, r.iso_after);
    h += "<p class=note>No prediction was made (--samples 0): there is no predicted after-state and no improvement "
         "figure. The " + std::string(kNominalLabel) + " column is ≈ 0 by construction and is not a result.</p>\n";
  }
  h += not_applicable_note(r.iso_before.parameters);
  if (r.measurement) {
    const auto& d = r.measurement->diagnosis;
    h += "<p class=verdict><b>Diagnosis</b> (measurement " + esc(r.measurement->file) + "): " +
         (d.chosen ? "the measurement shows an effect the scene does not model — <b>" + esc(d.chosen->name()) + "</b>. "
                   : std::string("no missing effect found. ")) +
         esc(d.verdict) + "</p>\n";
  }
  h += figures_of(figs, "topology");
  return h + "</section>\n";
}

/// Under a user's own effect (custom_effects) in the ranked table: its law as declared ("your effect (custom_effects):
/// deviation_um = …", or the Python function's name) and its closest look-alikes; empty for the library's.
std::string own_effect_note(const diagnosis::Candidate& c) {
  if (c.effects.size() != 1 || c.explanations.empty() || !effects::is_custom_effect(c.effects.front().type)) return {};
  std::string alike;
  for (size_t k = 0; k < c.look_alikes.size() && k < 3; ++k)
    alike += fmt::format("{}{} {:.3f}", k ? ", " : "; its field here is like (|ρ|) ", c.look_alikes[k].first,
                         c.look_alikes[k].second);
  return "<br><small>" + esc(c.explanations.front() + alike) + "</small>";
}

/// The run's date (UTC, ISO 8601): SOURCE_DATE_EPOCH when set (reproducible output), else now.
std::string run_date() {
  std::time_t t = std::time(nullptr);
  if (const char* e = std::getenv("SOURCE_DATE_EPOCH")) {
    char* end = nullptr;
    const long long v = std::strtoll(e, &end, 10);
    if (end != e && *end == '\0' && v >= 0) t = static_cast<std::time_t>(v);
  }
  std::tm tm{};
  gmtime_r(&t, &tm);
  return fmt::format("{:04d}-{:02d}-{:02d}", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday);
}

// Screen: up to 1400 px wide. Print (A4, 12 mm margins: 186 mm = 703 CSS px of printable width, which every table
// must fit — ReportTest.PrintEveryTableFitsTheA4PrintableWidth): 9 pt tables, figures at most 135 mm tall (the
// nominal after-state's, ≈ 0, 80 mm; the diagnosis' 100 mm; measured-vs-model up to a page, 250 mm, as its height grows with
// the measured flanks: 8 flanks at 120 mm were 60 mm wide, unreadable) so that pages fill, the first page a sheet of its own, long tables free to
// continue on the next page (their header repeated), and no other forced break.
const char* kStyle =
    "<style>*{box-sizing:border-box}html{font-size:16px}"
    "body{font-family:'DejaVu Sans',sans-serif;max-width:1400px;margin:0 auto;padding:1em 1.5em;color:#222;line-height:1.4}"
    "h1{font-size:1.6em;margin:.2em 0}h2{border-bottom:1px solid #ccc;padding-top:.6em;font-size:1.3em}"
    "table{border-collapse:collapse;margin:.8em 0;font-size:.92em}"
    "td,th{border:1px solid #bbb;padding:.2em .5em;text-align:right}th{background:#f2f2f2}td:first-child{text-align:left}"
    "table.header,table.data{width:100%}table.header th,table.data th{text-align:left;width:14%}"
    "table.header td,table.data td{text-align:left;overflow-wrap:anywhere}td.cls,span.cls{color:#666;font-size:.85em}table.flanks td{white-space:nowrap}"
    "table.ranked :is(td,th):nth-child(2),table.ranked :is(td,th):last-child{text-align:left}table.result td{white-space:nowrap}table.result td:first-child{white-space:normal}table.result tr.overall td{font-weight:bold;background:#f6f8fa}"
    ".pair{display:flex;flex-wrap:wrap;gap:0 1.5em;align-items:flex-start}"
    "figure{margin:1em 0}img{max-width:100%;height:auto;border:1px solid #ddd;display:block}"
    "figcaption{font-size:.9em;color:#444;max-width:75em}.scroll{max-width:100%;overflow-x:auto}"
    ".row{display:flex;flex-wrap:wrap;gap:1.2em;align-items:flex-start}.row figure{flex:1 1 620px;min-width:0;margin:0}"
    ".row .side{flex:0 1 430px}.first{background:#f6f8fa;border:1px solid #ccd;padding:.2em 1.2em .6em}"
    ".first h2{margin-top:.3em}.lead{font-size:1.05em}.warn{color:#a00}.verdict{border-left:4px solid #1f77b4;padding-left:.6em}"
    ".first figure img{max-height:560px;width:auto}"
    ".note{color:#666;font-size:.9em}pre{background:#f6f6f6;padding:.6em;overflow-x:auto}"
    "@page{size:A4;margin:12mm}"
    "@media print{body{max-width:none;padding:0;font-size:9.5pt;line-height:1.3}h1{font-size:1.45em}"
    "h2{break-after:avoid;font-size:1.2em;padding-top:.3em;margin:.6em 0 .3em}"
    "table{font-size:9pt;margin:.4em 0;break-inside:auto}tr{break-inside:avoid}thead{display:table-header-group}"
    "td,th{padding:.1em .35em}table.header th,table.data th{width:auto}"
    "figure{break-inside:avoid;margin:.5em 0}img{width:auto;max-height:135mm}img[src=\"topology_after.png\"]{max-height:80mm}img[src=\"measured_vs_model.png\"]{max-height:250mm}"
    "img[src=\"diagnosis.png\"]{max-height:100mm}figcaption{font-size:8.5pt}"
    ".scroll{overflow:visible}.first{break-after:page;border:none;background:none;padding:0}"
    ".first figure{display:flex;gap:1em;align-items:flex-end}.first figure img{max-height:50mm;max-width:62%}"
    ".row{flex-wrap:nowrap;gap:.8em}.row figure{flex:0 0 52%}.row figure img{max-height:90mm}.row figcaption{font-size:7.5pt}.row .side{flex:1 1 auto}"
    ".row table.values{font-size:8pt}}</style>";

} // namespace

namespace detail {
const char* page_style() { return kStyle; }
std::string html_escape(const std::string& s) { return esc(s); }
std::string page_date() { return run_date(); }
} // namespace detail

void write_html_report(const std::filesystem::path& dir, const workbench::Workbench& wb, const pipeline::PipelineResult& r,
                       const std::vector<Figure>& figs, const ReportOptions& options) {
  const int shown_class = shown_tolerance_class(wb, r);
  const auto crown = crowning_of(wb, r.before);
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width\">"
       "<title>geartopo report — " + esc(wb.scene.name) + "</title>\n" + kStyle + "</head><body>\n";
  h += "<h1>Gear flank inspection report — " + esc(or_dash(wb.scene.name)) + "</h1>\n";
  h += header_block(wb, r.iso_before.evaluation.conventions, options.date.value_or(run_date()));
  h += first_page(wb, r, figs);

  h += "<h2>Gear data</h2>\n";
  h += "<p class=note>Deviations in µm, plus material positive: topology grids along the flank normal, ISO 1328-1 values " +
       esc(evaluation::describe(r.iso_before.evaluation.conventions)) +
       " (docs/iso1328.md); teeth numbered clockwise seen from the datum face; flanks left/right per DIN ISO 21771; "
       "ISO 1328-1:2013 flank tolerance classes. The simulated state before compensation is evaluated unless a section "
       "says otherwise.</p>\n";
  h += gear_data_block(wb) + figures_of(figs, "gear");

  h += "<h2>Profile and helix</h2>\n";
  const bool classified = !evaluation::validity_refusal(r.iso_before.parameters);
  h += fmt::format("<p class=note>Trace charts {}. Values µm; F, f_f compared by size, f_H "
                   "signed (positive: material increases towards the tip / away from the datum face); C: crowning, the height "
                   "of the fitted parabola above its chord over the evaluation range (not toleranced by ISO 1328-1).</p>\n",
                   classified ? fmt::format("with tolerance boxes of class {} ({})", shown_class,
                                            wb.scene.report.tolerance_class ? "the scene's report.tolerance_class"
                                                                            : "the class achieved")
                              : std::string("without tolerance boxes") + kNotApplicableMark);
  for (const auto& f : figs)
    if (f.section == "traces")
      h += "<div class=row>" + figure_html(f) + "<div class=side>" + trace_value_table(r.iso_before, f.tooth, shown_class, crown) +
           "</div></div>\n";

  h += "<h2>ISO 1328-1:2013 — every evaluated flank</h2>\n<p class=note>Each value with its flank tolerance class in grey; "
       "C_α, C_β: crowning (not toleranced).</p>\n<div class=pair>" + flank_table(r.iso_before, Flank::Left, crown) +
       flank_table(r.iso_before, Flank::Right, crown) + "</div>\n";
  h += "<p>Mean slopes over the flanks evaluated, per side:</p>" + means_table(r.iso_before);
  h += "<h2>ISO 1328-1:2013 — worst values before compensation</h2>\n" + worst_values_table(r.iso_before);
  h += tolerance_table(r.iso_before.parameters, shown_class);
  h += figures_of(figs, "pitch") + figures_of(figs, "runout");

  h += "<h2>Machine</h2><p>" + esc(wb.scene.machine.name.empty() ? "machine without a name" : wb.scene.machine.name) +
       esc(fmt::format(", kinematic chain {} (axes {})", wb.scene.machine.chain->layout(), axes_of(*wb.scene.machine.chain))) +
       ".</p>\n";
  h += figures_of(figs, "machine");
  h += "<h2>Compensation (flank method)</h2>\n";
  if (r.corrections) {
    const auto m = r.corrections->max_abs();
    const auto ax = [&](int i) { return r.corrections->axes().axis_name(i); }; // the chain's own axes
    h += fmt::format("<p>{} path samples; largest corrections {} {:.2f} µm, {} {:.2f} µm, {} {:.2f} µm, {} {:.2f} µrad, {} {:.2f} µrad; "
                     "{} samples outside the strokes. The correction table is corrections.csv.</p>\n",
                     r.corrections->rows().size(), ax(0), units::um_from_mm(m(0)), ax(1), units::um_from_mm(m(1)), ax(2), units::um_from_mm(m(2)), ax(3), units::urad_from_rad(m(3)), ax(4),
                     units::urad_from_rad(m(4)), r.corrections->rows_outside_strokes());
  }
  h += fmt::format("<p class=note>The {}: largest |deviation| {:.2f} µm, overall class {} — ≈ 0 by construction, a check "
                   "of the corrections against the model, not a result; the result is the prediction{}.</p>\n",
                   kNominalLabel, r.largest_after_um, class_text(r.iso_after.evaluation.classification.overall, r.iso_after.parameters),
                   r.prediction ? " (first page, and the figure below)" : ", not made here (--samples 0)");
  h += figures_of(figs, "compensation");
  if (r.measurement) {
    const auto& m = *r.measurement;
    h += "<h2>Model vs measurement</h2>\n";
    h += fmt::format("<p>{} points from {}; residual (measured − model) {:.2f} µm RMS, max {:.2f} µm; noise {:.2f} µm.</p>\n",
                     m.points.size(), esc(m.file), m.before.summary.overall.rms_um, m.before.summary.overall.max_abs_um,
                     m.before.noise_um);
    if (!m.before.regions.empty()) {
      h += "<p>Where the model fails:</p><ul>";
      for (const auto& reg : m.before.regions) h += "<li>" + esc(reg.sentence) + "</li>";
      h += "</ul>\n";
    }
    h += figures_of(figs, "measurement");
    h += "<div class=scroll><table class=ranked><thead><tr><th>rank</th><th>effect</th><th>ΔBIC</th><th>explained</th><th>RMS after (µm)</th>"
         "<th>parameters (±1σ)</th></tr></thead>"; // thead: repeated when the table continues on the next printed page
    int rank = 1;
    for (const auto& c : m.diagnosis.ranked) {
      std::string params;
      for (const auto& p : c.parameters.front())
        if (p.fitted) // GUM §7.2.6; a value the data do not fix is no finding
          params += fmt::format("{} {}; ", p.key, p.determined ? text::with_uncertainty(p.value, p.uncertainty)
                                                               : std::string("not determined"));
      if (params.ends_with("; ")) params.resize(params.size() - 2); // a separator, not a terminator
      h += fmt::format("<tr><td>{}</td><td>{}{}{}</td><td>{:.1f}</td><td>{:.1f} %</td><td>{:.2f}</td><td>{}</td></tr>", rank++,
                       esc(c.name()), c.significant ? "" : " (not significant)", own_effect_note(c), c.delta_bic,
                       100 * c.explained_fraction, c.rms_after_um, esc(params));
    }
    h += "</table></div>\n";
    if (!m.diagnosis.hypotheses.empty()) {
      // Beyond the library (docs/diagnosis.md): the machine's own elements, best first.
      h += "<p>Beyond the library: the chain's error components under their laws in time, and each wheel flank.</p>\n"
           "<div class=scroll><table class=ranked><thead><tr><th>rank</th><th>machine element and law</th><th>ΔBIC</th>"
           "<th>explained</th><th>finding</th></tr></thead>";
      int k = 1;
      for (const auto& row : diagnosis::hypothesis_rows(m.diagnosis)) { // an equivalence class is one row
        const auto& c = *row.hypothesis;
        const std::string members =
            row.members.empty() ? std::string() : "<br><small>" + esc(diagnosis::members_text(row)) + "</small>";
        h += fmt::format("<tr><td>{}</td><td>{}{}</td><td>{:.1f}</td><td>{:.1f} %</td><td>{}{}</td></tr>", k++,
                         esc(c.name()), members, c.delta_bic, 100 * c.explained_fraction, esc(c.description),
                         c.rejection ? esc(" (rejected: " + diagnosis::to_text(*c.rejection) + ")") : std::string());
      }
      h += "</table></div>\n";
    }
    h += "<p><b>Verdict.</b> " + esc(m.diagnosis.verdict) + "</p>\n";
    if (m.after)
      h += fmt::format("<p>With the effect added the residual falls from {:.2f} to {:.2f} µm RMS (scene_with_effect.yaml).</p>\n",
                       m.before.summary.overall.rms_um, m.after->summary.overall.rms_um);
  }
  h += "<p class=note>Made by geartopo. Files in this folder: the PNGs above, figures.json";
  h += r.measurement ? ", and with <code>geartopo run</code> the data files (CSV, JSON).</p>" : ".</p>";
  h += "</body></html>\n";
  output::write_text_atomically(dir / "index.html", h);
}

std::vector<Figure> write_report(const std::filesystem::path& dir, const workbench::Workbench& wb, const pipeline::PipelineResult& r,
                                 const ReportOptions& options, std::vector<Figure> before) {
  auto figs = render_figures(wb, r, dir, std::move(before));
  write_html_report(dir, wb, r, figs, options);
  nlohmann::json man = nlohmann::json::array();
  for (const auto& f : figs) {
    nlohmann::json j{{"file", f.file},   {"section", f.section}, {"title", f.title},
                     {"width", f.width}, {"height", f.height},   {"shared_scale", f.shared_scale}};
    j["data_range_um"] = f.data_range_um ? nlohmann::json{f.data_range_um->first, f.data_range_um->second} : nlohmann::json(nullptr);
    j["colour_range_um"] = f.colour_range_um ? nlohmann::json{f.colour_range_um->first, f.colour_range_um->second} : nlohmann::json(nullptr);
    if (!f.charts.empty()) {
      nlohmann::json charts = nlohmann::json::array();
      for (const auto& c : f.charts)
        charts.push_back({{"panel", c.panel},
                          {"data_range_um", {c.data_um.first, c.data_um.second}},
                          {"tolerance_box_um", {c.tolerance_um.first, c.tolerance_um.second}},
                          {"axis_range_um", {c.axis_um.first, c.axis_um.second}},
                          {"min_span_um", c.min_span_um}});
      j["charts"] = charts;
    }
    man.push_back(j);
  }
  output::write_text_atomically(dir / "figures.json", man.dump(2) + "\n");
  return figs;
}

} // namespace geartopo::report
