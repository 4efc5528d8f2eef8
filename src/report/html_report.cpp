#include "geartopo/report/html_report.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/core/atomic_file.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/report/iso_report.hpp"

#include "geartopo/evaluation/tolerances.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <numbers>

namespace geartopo::report {
namespace {

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

std::string figures_of(const std::vector<Figure>& figs, const std::string& section) {
  std::string h;
  for (const auto& f : figs)
    if (f.section == section)
      h += fmt::format("<figure><img src=\"{}\" alt=\"{}\" width=\"{}\"><figcaption><b>{}</b> — {}</figcaption></figure>\n",
                       esc(f.file), esc(f.title), std::min(f.width, 1400), esc(f.title), esc(f.caption));
  return h;
}

std::string iso_table(const workbench::IsoResult& b, const workbench::IsoResult& a) {
  std::string h = "<table><tr><th>quantity</th><th>before (µm)</th><th>class</th><th>where</th><th>after (µm)</th><th>class</th>"
                  "<th>better</th></tr>\n";
  const auto& qb = b.evaluation.classification.quantities;
  const auto& qa = a.evaluation.classification.quantities;
  for (size_t i = 0; i < qb.size() && i < qa.size(); ++i) {
    const double imp = std::abs(qb[i].worst_value_um) > 0 ? 100.0 * (std::abs(qb[i].worst_value_um) - std::abs(qa[i].worst_value_um)) /
                                                                std::abs(qb[i].worst_value_um)
                                                          : 0.0;
    h += fmt::format("<tr><td>{}</td><td>{:.2f}</td><td>{}</td><td>{}</td><td>{:.2f}</td><td>{}</td><td>{:.0f} %</td></tr>\n",
                     esc(std::string(evaluation::symbol(qb[i].quantity))), qb[i].worst_value_um, evaluation::class_label(qb[i].flank_class),
                     esc(qb[i].where), qa[i].worst_value_um, evaluation::class_label(qa[i].flank_class), imp);
  }
  const auto& cb = b.evaluation.classification;
  const auto& ca = a.evaluation.classification;
  if (cb.refusal) h += "<tr><td colspan=7>Classification refused: " + esc(*cb.refusal) + "</td></tr>";
  h += fmt::format("<tr><th>overall class</th><th colspan=3>{}</th><th colspan=3>{}</th></tr></table>\n", evaluation::class_label(cb.overall),
                   evaluation::class_label(ca.overall));
  return h;
}

} // namespace

void write_html_report(const std::filesystem::path& dir, const workbench::Workbench& wb, const pipeline::PipelineResult& r,
                       const std::vector<Figure>& figs) {
  const auto& g = wb.setup.geometry();
  const auto& s = g.spec();
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>geartopo report — " + esc(wb.scene.name) +
       "</title>\n<style>body{font-family:sans-serif;max-width:1460px;margin:2em auto;color:#222;line-height:1.4}"
       "h1{font-size:1.6em}h2{border-bottom:1px solid #ccc;padding-top:.6em}table{border-collapse:collapse;margin:1em 0}"
       "td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right}th{background:#f2f2f2}td:first-child{text-align:left}"
       "figure{margin:1.2em 0}img{max-width:100%;height:auto;border:1px solid #ddd}figcaption{font-size:.9em;color:#444}"
       ".box{background:#f6f8fa;border:1px solid #ccd;padding:.8em 1.2em}.note{color:#666;font-size:.9em}pre{background:#f6f6f6;"
       "padding:.6em;overflow-x:auto}</style></head><body>\n";
  h += "<h1>geartopo report — " + esc(wb.scene.name) + "</h1>\n";
  h += "<p class=note>Deviations in µm along the flank normal, plus material positive; teeth numbered clockwise seen from "
       "the datum face; ISO 1328-1:2013 flank tolerance classes. Every figure is a PNG in this folder.</p>\n";

  h += "<div class=box><h3>Summary</h3><ul>";
  const auto& cb = r.iso_before.evaluation.classification;
  const auto& ca = r.iso_after.evaluation.classification;
  if (r.prediction) {
    h += prediction_summary_html(*r.prediction); // the after-state as a band (prediction_report.hpp)
  } else {
    h += fmt::format("<li>Largest |deviation| of the {} grids, all teeth: <b>{:.2f} µm</b> before; the nominal model "
                     "compensating itself (flank method): {:.2f} µm — no prediction was made (--samples 0).</li>",
                     grid_label(r), r.largest_before_um, r.largest_after_um);
    h += fmt::format("<li>Overall flank tolerance class: <b>{}</b> before, {} nominal after.</li>", evaluation::class_label(cb.overall), evaluation::class_label(ca.overall));
  }
  if (r.measurement) h += "<li>Diagnosis: " + esc(r.measurement->diagnosis.verdict) + "</li>";
  h += "</ul></div>\n";

  h += "<h2>Gear</h2><table>";
  const auto row = [&](const std::string& k, const std::string& v) { h += "<tr><td>" + esc(k) + "</td><td>" + esc(v) + "</td></tr>"; };
  row("normal module m_n", fmt::format("{} mm", s.normal_module_mm));
  row("teeth z", std::to_string(s.teeth));
  row("normal pressure angle α_n", fmt::format("{:.3f}°", s.normal_pressure_angle_rad * 180 / std::numbers::pi));
  row("helix angle β", fmt::format("{:.3f}° ({} hand)", s.helix_angle_rad * 180 / std::numbers::pi, gears::to_string(s.hand())));
  row("profile shift x", fmt::format("{}", s.profile_shift));
  row("face width b", fmt::format("{} mm", s.face_width_mm));
  row("reference / base / tip / root diameter", fmt::format("{:.3f} / {:.3f} / {:.3f} / {:.3f} mm", g.reference_diameter_mm(),
                                                            g.base_diameter_mm(), g.tip_diameter_mm(), g.root_diameter_mm()));
  if (!wb.scene.assumed.empty()) row("assumed (not from a drawing)", fmt::format("{}", fmt::join(wb.scene.assumed, ", ")));
  h += "</table>\n" + figures_of(figs, "gear");

  h += "<h2>Machine</h2><p>" + esc(wb.scene.machine.name.empty() ? "machine without a name" : wb.scene.machine.name) + ".</p>\n";
  h += figures_of(figs, "machine");
  h += "<h2>Topology before compensation</h2>\n" + figures_of(figs, "topology") + figures_of(figs, "traces") +
       figures_of(figs, "pitch");
  h += "<h2>ISO 1328-1:2013 — before and after compensation</h2>\n" + iso_table(r.iso_before, r.iso_after);
  if (const auto t = class5_tolerances_json(r.iso_before.parameters); !t.is_null()) {
    h += "<p class=note>Class-5 tolerances (µm): ";
    for (auto it = t.begin(); it != t.end(); ++it) h += esc(it.key()) + " " + fmt::format("{}", it.value().get<double>()) + "; ";
    h += "</p>\n";
  }
  h += "<h2>Compensation (flank method)</h2>\n";
  if (r.corrections) {
    const auto m = r.corrections->max_abs();
    h += fmt::format("<p>{} path samples; largest corrections X {:.2f} µm, Y {:.2f} µm, Z {:.2f} µm, A {:.2f} µrad, C {:.2f} µrad; "
                     "{} samples outside the strokes. The correction table is corrections.csv.</p>\n",
                     r.corrections->rows().size(), units::um_from_mm(m(0)), units::um_from_mm(m(1)), units::um_from_mm(m(2)), units::urad_from_rad(m(3)), units::urad_from_rad(m(4)),
                     r.corrections->rows_outside_strokes());
  }
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
    h += "<table><tr><th>rank</th><th>effect</th><th>ΔBIC</th><th>explained</th><th>RMS after (µm)</th><th>parameters (±1σ)</th></tr>";
    int rank = 1;
    for (const auto& c : m.diagnosis.ranked) {
      std::string params;
      for (const auto& p : c.parameters.front())
        if (p.fitted) params += fmt::format("{} {:.4g} ± {:.2g}; ", p.key, p.value, p.uncertainty);
      h += fmt::format("<tr><td>{}</td><td>{}{}</td><td>{:.1f}</td><td>{:.1f} %</td><td>{:.2f}</td><td>{}</td></tr>", rank++,
                       esc(c.name()), c.significant ? "" : " (not significant)", c.delta_bic, 100 * c.explained_fraction,
                       c.rms_after_um, esc(params));
    }
    h += "</table>\n<p><b>Verdict.</b> " + esc(m.diagnosis.verdict) + "</p>\n";
    if (m.after)
      h += fmt::format("<p>With the effect added the residual falls from {:.2f} to {:.2f} µm RMS (scene_with_effect.yaml).</p>\n",
                       m.before.summary.overall.rms_um, m.after->summary.overall.rms_um);
  }
  h += "<p class=note>Made by geartopo. Files in this folder: the PNGs above, figures.json";
  h += r.measurement ? ", and with <code>geartopo run</code> the data files (CSV, JSON).</p>" : ".</p>";
  h += "</body></html>\n";
  output::write_text_atomically(dir / "index.html", h);
}

std::vector<Figure> write_report(const std::filesystem::path& dir, const workbench::Workbench& wb, const pipeline::PipelineResult& r) {
  auto figs = render_figures(wb, r, dir);
  write_html_report(dir, wb, r, figs);
  nlohmann::json man = nlohmann::json::array();
  for (const auto& f : figs) {
    nlohmann::json j{{"file", f.file},   {"section", f.section}, {"title", f.title},
                     {"width", f.width}, {"height", f.height},   {"shared_scale", f.shared_scale}};
    j["data_range_um"] = f.data_range_um ? nlohmann::json{f.data_range_um->first, f.data_range_um->second} : nlohmann::json(nullptr);
    j["colour_range_um"] = f.colour_range_um ? nlohmann::json{f.colour_range_um->first, f.colour_range_um->second} : nlohmann::json(nullptr);
    man.push_back(j);
  }
  output::write_text_atomically(dir / "figures.json", man.dump(2) + "\n");
  return figs;
}

} // namespace geartopo::report
