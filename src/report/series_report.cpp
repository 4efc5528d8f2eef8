// The report page of a production series (series_report.hpp).
#include "geartopo/report/series_report.hpp"

#include "html_common.hpp"

#include "geartopo/aqdef/aqdef.hpp"
#include "geartopo/core/uncertain_value.hpp"
#include "geartopo/files/atomic_write.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace geartopo::report {
namespace {

using detail::html_escape;

std::string dash_if_empty(const std::string& s) { return s.empty() ? "—" : s; }

std::string header(const workbench::Workbench& wb, const series::SeriesResult& r, const std::string& date) {
  const auto& rep = wb.scene.report;
  const std::string machine = !r.spec.machine.empty() ? r.spec.machine : wb.scene.machine.name;
  std::string started = "—";
  if (r.spec.started_epoch_s) started = aqdef::format_time(*r.spec.started_epoch_s);
  return fmt::format(
      "<table class=header><tr><th>Series</th><td>{}</td><th>Series file</th><td>{}</td></tr>"
      "<tr><th>Part</th><td>{}</td><th>Drawing</th><td>{}</td></tr>"
      "<tr><th>Machine</th><td>{}</td><th>Series started</th><td>{}</td></tr>"
      "<tr><th>Gears measured</th><td>{} ({} strokes per gear)</td><th>Drawing class</th><td>{}</td></tr>"
      "<tr><th>Scene</th><td>{}</td><th>Date</th><td>{}</td></tr></table>\n",
      html_escape(dash_if_empty(r.spec.name)), html_escape(r.spec.source), html_escape(dash_if_empty(rep.part)),
      html_escape(dash_if_empty(rep.drawing)), html_escape(dash_if_empty(machine)), html_escape(started), r.gears.size(),
      r.strokes_per_gear, r.drawing_class ? fmt::format("{} (ISO 1328-1:2013)", *r.drawing_class) : std::string("not given"),
      html_escape(r.spec.scene.string()), html_escape(date));
}

std::string opt_um(const std::optional<double>& v) { return v ? fmt::format("{:.2f}", *v) : std::string("—"); }

/// A gear's within-job diagnosis in a table cell: the explanation named (withheld: so marked), else why none.
std::string within_job(const series::GearValues& g) {
  if (!g.diagnosis) return "–";
  const auto& d = *g.diagnosis;
  if (d.chosen) return d.chosen->name() + (d.withheld ? " (withheld)" : "");
  return d.unexplained ? "unexplained (more than noise)" : "nothing beyond noise";
}

/// One row per gear: when, the wheel and corrections state, the residual, the ISO class; pitch and runout when any
/// gear has them.
std::string per_gear_table(const series::SeriesResult& r) {
  bool pitch = false;
  for (const auto& g : r.gears)
    pitch = pitch || (g.iso && (g.iso->evaluation.pitch_left || g.iso->evaluation.pitch_right || g.iso->evaluation.runout));
  std::string h = "<div class=scroll><table class=pergear><thead><tr><th>#</th><th>gear</th><th>start (h)</th><th>strokes since "
                  "dressing</th><th>corrections</th><th>residual L (µm)</th><th>residual R (µm)</th><th>RMS (µm)</th>"
                  "<th>ISO class</th>";
  if (pitch) h += "<th>f_p L (µm)</th><th>F_p L (µm)</th><th>f_p R (µm)</th><th>F_p R (µm)</th><th>F_r (µm)</th>";
  const bool diagnosed = std::any_of(r.gears.begin(), r.gears.end(), [](const auto& g) { return g.diagnosis.has_value(); });
  if (diagnosed) h += "<th>within the job (diagnose)</th>";
  h += "</tr></thead>\n";
  for (size_t k = 0; k < r.gears.size(); ++k) {
    const auto& g = r.gears[k];
    const auto cls = g.iso ? g.iso->evaluation.classification.overall : std::optional<int>{};
    h += fmt::format("<tr><td>{}</td><td>{}</td><td>{:.2f}</td><td>{:.0f}{}</td><td>{}</td><td>{:+.2f}</td><td>{:+.2f}</td>"
                     "<td>{:.2f}</td><td>{}</td>",
                     k + 1, html_escape(g.gear.id), g.gear.start_s / 3600.0, g.gear.strokes_since_dressing,
                     g.gear.dressed_before ? " (re-dressed)" : "",
                     g.gear.corrections.empty() ? std::string("none") : fmt::format("set {}", g.correction_set),
                     g.mean_residual_um[0], g.mean_residual_um[1], g.rms_residual_um,
                     g.iso ? html_escape(evaluation::class_label(cls)) : std::string("–"));
    if (pitch) {
      const auto* e = g.iso ? &g.iso->evaluation : nullptr;
      const auto pl = e && e->pitch_left ? &*e->pitch_left : nullptr;
      const auto pr = e && e->pitch_right ? &*e->pitch_right : nullptr;
      h += fmt::format("<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>",
                       opt_um(pl ? std::optional(pl->f_p_um) : std::nullopt), opt_um(pl ? std::optional(pl->F_p_um) : std::nullopt),
                       opt_um(pr ? std::optional(pr->f_p_um) : std::nullopt), opt_um(pr ? std::optional(pr->F_p_um) : std::nullopt),
                       opt_um(e && e->runout ? std::optional(e->runout->F_r_um) : std::nullopt));
    }
    if (diagnosed) h += "<td>" + html_escape(within_job(g)) + "</td>";
    h += "</tr>\n";
  }
  h += "</table></div>\n";
  if (diagnosed) {
    h += "<p>Each gear's measurement through <code>geartopo diagnose</code>'s pipeline, against the model it was ground "
         "with (its corrections included); the verdicts:</p>\n<ul class=verdicts>\n";
    for (const auto& g : r.gears)
      if (g.diagnosis) h += fmt::format("<li><b>{}</b>: {}</li>\n", html_escape(g.gear.id), html_escape(g.diagnosis->verdict));
    h += "</ul>\n";
  }
  return h;
}

/// A law's parameter in the symbols of the page's formula: "τ = 0.9995 ± 0.0010 h".
std::string parameter_line(const series::FittedParameter& p) {
  std::string symbol = p.name, unit = "µm";
  if (p.name == "offset_um") symbol = "c";
  else if (p.name == "thermal_amplitude_um") symbol = "a";
  else if (p.name == "time_constant_h") symbol = "τ", unit = "h";
  else if (p.name == "wear_um_per_stroke") symbol = "w", unit = "µm/stroke";
  else if (p.name.rfind("step_", 0) == 0) symbol = "d_" + p.name.substr(5, p.name.size() - 8);
  if (!p.determined) return symbol + " not determined";
  return fmt::format("{} = {} {}", symbol, text::with_uncertainty(p.value, p.sigma), unit);
}

std::string parameters_html(const series::LawFit& f) {
  std::string s;
  for (const auto& p : f.parameters) s += (s.empty() ? "" : "<br>") + html_escape(parameter_line(p));
  return s;
}

std::string loss_text(const series::SeriesQuantity& q) {
  if (!q.loss) return "no limit";
  const auto& c = *q.loss;
  if (c.already) return "outside at the next gear";
  if (!c.gears_median)
    return c.gears_early ? fmt::format("kept as far as looked (95 %: may be left {} gears ahead)", *c.gears_early)
                         : std::string("kept as far as looked");
  return fmt::format("{} gears ahead (95 %: {} … {}); job start {:.0f} strokes after dressing, {:.2f} h", *c.gears_median,
                     *c.gears_early, c.gears_late ? std::to_string(*c.gears_late) : std::string("later"),
                     c.strokes_median.value_or(NAN), c.time_median_h.value_or(NAN));
}

/// The findings: per quantity its law with σ, the scatter left, the next gear and the class loss.
std::string findings_table(const series::SeriesResult& r) {
  if (std::none_of(r.quantities.begin(), r.quantities.end(), [](const auto& q) { return q.fit.has_value(); })) return "";
  std::string h = "<div class=scroll><table class=findings><thead><tr><th>quantity (µm)</th><th>law across the series "
                  "(scatter left)</th><th>parameters (±1σ)</th><th>next gear: median [95 %]</th><th>limit</th>"
                  "<th>limit expected left</th></tr></thead>\n";
  for (const auto& q : r.quantities) {
    if (!q.fit) continue;
    const auto& f = q.fit->chosen;
    h += fmt::format("<tr><td>{}</td><td>{} ({:.2f} µm)</td><td>{}</td><td>{:+.2f} [{:+.2f}, {:+.2f}]</td><td>{}</td>"
                     "<td>{}</td></tr>\n",
                     html_escape(q.label), html_escape(f.name()), f.sigma_um, parameters_html(f), q.next->median_um,
                     q.next->lower95_um, q.next->upper95_um,
                     q.limit_um ? fmt::format("{}{:.1f}", series::two_sided_limit(q) ? "±" : "≤ ", *q.limit_um)
                                : std::string("—"),
                     html_escape(loss_text(q)));
  }
  return h + "</table></div>\n";
}

/// The re-dress / re-compensation interval: the earliest expected class loss over the quantities, and which law drives it.
std::string interval_text(const series::SeriesResult& r) {
  const series::SeriesQuantity* first = nullptr;
  for (const auto& q : r.quantities)
    if (q.loss && q.loss->gears_median && (!first || *q.loss->gears_median < *first->loss->gears_median)) first = &q;
  if (r.gears.size() < 3)
    return fmt::format("<p>{} gear(s) measured: the laws across the series need 3 or more; nothing is fitted or "
                       "predicted yet.</p>\n", r.gears.size());
  if (!first)
    return "<p>No quantity is expected to leave its limit within the gears looked ahead: no re-dress or "
           "re-compensation is called for by the series.</p>\n";
  const auto& c = *first->loss;
  const auto& f = first->fit->chosen;
  const bool wear = std::find(f.laws.begin(), f.laws.end(), series::Law::WheelWear) != f.laws.end();
  return fmt::format(
      "<p class=verdict><b>{}</b> {} is expected to leave its limit first: {} gears after the last measured one (95 %: "
      "{} … {}), at a job starting {:.0f} strokes after dressing, {:.2f} h after the series start — the law: {}. {}</p>\n",
      wear ? "Re-dress interval." : "Re-compensation interval.", html_escape(first->label), *c.gears_median,
      *c.gears_early, c.gears_late ? std::to_string(*c.gears_late) : std::string("later"), c.strokes_median.value_or(NAN),
      c.time_median_h.value_or(NAN), html_escape(f.name()),
      wear ? "Re-dress the wheel before that many strokes; the early end is the safe interval."
           : "Correct the machine (a new compensation) before then; the early end is the safe interval.");
}

std::string figure(const std::string& file, const std::string& title, const std::string& caption) {
  return fmt::format("<figure><img src=\"{}\" alt=\"{}\" width=\"1200\" height=\"800\"><figcaption><b>{}.</b> {}"
                     "</figcaption></figure>\n", html_escape(file), html_escape(title), html_escape(title), html_escape(caption));
}

std::string figures(const series::SeriesResult& r, const SeriesFigures& figs) {
  std::string h = "<div class=charts>";
  for (const auto& f : figs.run_charts) {
    const std::string key = f.stem().string().substr(std::string("run_chart_").size());
    std::string label = key;
    for (const auto& q : r.quantities)
      if (q.key == key) label = q.label;
    h += figure(f.filename().string(), label, "");
  }
  return h + "</div>\n";
}

// The series page's own rules on top of the report's: the findings left-aligned and wrapping, the run charts two
// to a row on screen and on paper.
const char* kSeriesStyle =
    "<style>table.findings td{text-align:left;vertical-align:top}table.findings td:first-child{min-width:8em}"
    "table.findings td:nth-child(3),table.findings td:nth-child(4),table.findings td:nth-child(5){white-space:nowrap}"
    "table.pergear td{white-space:nowrap}"
    ".charts{display:grid;grid-template-columns:1fr 1fr;gap:.6em 1.2em}.charts figure{margin:0}"
    "@media print{.charts img{max-height:62mm}table.findings,table.pergear{font-size:8pt}table.pergear td{padding:.1em .25em}}</style>";

} // namespace

void write_series_report(const std::filesystem::path& dir, const workbench::Workbench& wb, const series::SeriesResult& r,
                         const SeriesFigures& figs, const ReportOptions& options) {
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" "
                  "content=\"width=device-width\"><title>geartopo series report — " + html_escape(dash_if_empty(r.spec.name)) +
                  "</title>\n" + detail::page_style() + kSeriesStyle + "</head><body>\n";
  h += "<h1>Production series report — " + html_escape(dash_if_empty(r.spec.name)) + "</h1>\n";
  h += header(wb, r, options.date.value_or(detail::page_date()));
  h += "<section class=first><h2>Across the series</h2>\n" + interval_text(r);
  h += "<p class=note>Each quantity fitted over the gears with the laws thermal drift c + a (1 − e^(−t/τ)), wheel wear "
       "c + w S (S: strokes since dressing, reset by a re-dress) and a step per change of corrections; a law kept only "
       "when an F-test at 1 % rejects the smaller model; σ from the fit's covariance; \"not determined\" where the "
       "series does not fix a value (docs/series.md). Deviations plus material positive, µm.</p>\n";
  h += findings_table(r) + "</section>\n";
  h += "<h2>Per gear</h2>\n<p class=note>Residual: measured − model without the gear's corrections, mean over the used "
       "points of each flank side; ISO class: ISO 1328-1:2013 of the gear's traces; pitch and runout when every tooth "
       "was measured.</p>\n" + per_gear_table(r);
  h += "<h2>Run charts</h2>\n<p class=note>Each quantity per gear in the order ground (blue), its straight-line trend "
       "and mean (grey), the law chosen across the series (red) and the next gear's 95 % interval (orange); the "
       "drawing's tolerance shaded where it has one.</p>\n" + figures(r, figs);
  if (figs.closed_loop)
    h += "<h2>Closed loop over the series (synthetic)</h2>\n" +
         figure(figs.closed_loop->filename().string(), "Closed loop over the series — synthetic",
                "Not measured: the law fitted to this series taken as the truth, its scatter drawn, the series' gears "
                "stepped on; open loop against gear k's series diagnosis (the laws fitted to gears 1 … k) correcting "
                "gear k + 1. It shows what feeding the diagnosis back would do, not what was done.");
  h += "<p class=note>Made by geartopo series. Files in this folder: series.json, the PNGs above.</p>\n</body></html>\n";
  output::write_text_atomically(dir / "index.html", h);
}

} // namespace geartopo::report
