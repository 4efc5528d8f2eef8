#include "app/run_command.hpp"

#include "app/commands.hpp"
#include "app/compensation_warnings.hpp"
#include "app/json_summary.hpp"
#include "app/messages.hpp"
#include "app/parsers.hpp"
#include "app/pipeline_job.hpp"

#include "geartopo/report/html_report.hpp"
#include "geartopo/report/improvement.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <fmt/format.h>

#include <iostream>

namespace geartopo::app {
namespace {

void print_job_summary(const std::filesystem::path& dir, const pipeline::PipelineResult& r) {
  const auto& cb = r.iso_before.evaluation.classification;
  const auto& ca = r.iso_after.evaluation.classification;
  if (r.prediction) { // the after-state as a band (docs/monte-carlo.md), never the model's own ≈ 0
    for (const auto& l : report::prediction_lines(*r.prediction)) std::cout << l << "\n";
    const auto imp = report::predicted_improvement(*r.prediction);
    for (const auto& i : imp)
      if (i.name == "largest_abs_um")
        std::cout << fmt::format("Predicted improvement of the largest |deviation|: {} (medians; interval: the after-state's "
                                 "95 % interval against the before-median; every quantity in iso1328.json)\n",
                                 report::improvement_text(i));
  } else {
    std::cout << fmt::format("Largest |deviation| ({} grids, all teeth): {:.2f} µm before; {}: {:.2f} µm (no prediction: "
                             "--samples 0, so no improvement figure)\n",
                             pipeline::grid_label(r), r.largest_before_um, report::kNominalLabel, r.largest_after_um);
    std::cout << fmt::format("ISO 1328-1 overall flank tolerance class: {} before; {}: {}{}\n",
                             evaluation::class_label(cb.overall), report::kNominalLabel, evaluation::class_label(ca.overall),
                             cb.refusal ? fmt::format(" (no class: ISO 1328-1:2013 does not apply to this gear: {})", *cb.refusal)
                             : cb.governing ? fmt::format(" (before: set by {})", evaluation::symbol(*cb.governing))
                                            : std::string());
  }
  if (r.measurement) {
    const auto& m = *r.measurement;
    std::cout << fmt::format("Measurement {}: residual {:.2f} µm RMS against the model\n", m.file, m.before.summary.overall.rms_um);
    if (!m.diagnosis.ranked.empty())
      std::cout << fmt::format("Top diagnosis: {} (ΔBIC {:.1f}, explains {:.0f} %)\n", m.diagnosis.ranked.front().name(),
                               m.diagnosis.ranked.front().delta_bic, 100 * m.diagnosis.ranked.front().explained_fraction);
    std::cout << m.diagnosis.verdict << "\n";
  }
  std::cout << "Report: " << (dir / "index.html").string() << "\n";
}

/// The pipeline's options from the command line: simulation, compensation, measurement, ISO options, prediction.
pipeline::PipelineOptions pipeline_options(const RunOptions& opt, const Workbench& wb) {
  pipeline::PipelineOptions po;
  po.method = opt.simulation == "linear" ? grinding::Method::Linear : grinding::Method::Exact;
  refuse_paper_on_a_designed_helix(opt.method, wb);
  po.compensation = opt.method == "paper"   ? compensation::Method::Paper
                    : opt.method == "cycle" ? compensation::Method::Cycle
                                            : compensation::Method::Flank;
  po.step_mm = opt.step;
  po.noise_um = opt.noise;
  set_measurement(po, wb, opt.measured, opt.mka);
  po.iso = opt.iso;
  po.prediction = prediction_options(opt.mc);
  return po;
}

} // namespace

int run_main_job(const RunOptions& opt) {
  JsonSummary json(opt.json);
  const output::RunFiles files = report_files(opt.scene, opt.measured);
  output::check_run_files(opt.out, files); // before any work: no input and no user's file is replaced
  // --teeth stands in for the scene's measurement.teeth: simulated, shown in the figures and the page.
  scene::Scene sc = scene::load_scene(opt.scene);
  if (opt.teeth_given) sc.grid.teeth = parse_teeth(opt.teeth, sc.gear.teeth);
  const Workbench wb(std::move(sc));
  pipeline::PipelineOptions po = pipeline_options(opt, wb);
  const std::filesystem::path dir(opt.out);
  output::OutputFolder folder(dir, files);
  if (!quiet()) say("geartopo run: " + (wb.scene.name.empty() ? opt.scene : wb.scene.name));
  print_notes(wb);
  ReportJob job = run_report_job(wb, po, opt.scene, dir, opt.mc.max_time_s);
  const pipeline::PipelineResult& r = job.result;
  nlohmann::json& summary = job.iso;
  print_job_summary(dir, r);
  finish_output_folder(folder);
  summary["report"] = (dir / "index.html").string();
  if (r.measurement) {
    const auto& d = r.measurement->diagnosis;
    summary["measurement"] = {{"file", r.measurement->file},
                              {"residual_rms_um", r.measurement->before.summary.overall.rms_um},
                              {"noise_um", r.measurement->before.noise_um},
                              {"chosen", d.chosen ? nlohmann::json(d.chosen->name()) : nlohmann::json(nullptr)},
                              {"ambiguous", !d.rivals.empty()},
                              {"verdict", d.verdict}};
  }
  json.emit(summary);
  return 0;
}

} // namespace geartopo::app
