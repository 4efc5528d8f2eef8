#include "app/pipeline_job.hpp"

#include "app/compensation_warnings.hpp"
#include "app/messages.hpp"
#include "app/monte_carlo_flags.hpp"

#include "geartopo/diagnosis/diagnosis_json.hpp"
#include "geartopo/diagnosis/identified_effects.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/diagnosis/scene_writer.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/report/html_report.hpp"
#include "geartopo/report/improvement.hpp"
#include "geartopo/report/iso_report.hpp"
#include "geartopo/report/measurement_report.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <algorithm>

namespace geartopo::app {

namespace fs = std::filesystem;

std::string measured_of(const workbench::Workbench& wb, const std::string& option) {
  return option.empty() ? wb.scene.grid.measured_file : option;
}

output::RunFiles report_files(const std::string& scene, const std::string& measured) {
  return {{scene, measured},
          {"index.html", "iso1328.json", "corrections.csv", "topology_before.csv", "topology_after.csv",
           "traces_before.csv", "traces_after.csv"}};
}

namespace {

/// iso1328.json: the gear before, the nominal after-state, the prediction and improvement, the warnings.
nlohmann::json iso_file(const fs::path& dir, const workbench::Workbench& wb, const pipeline::PipelineResult& r) {
  nlohmann::json iso;
  iso["scene"] = wb.scene.name;
  iso["units"] = "µm; plus material positive; profile/helix values in the direction each section names (iso_direction)";
  iso["before"] = report::iso_json(r.iso_before);
  // The model corrected by itself (≈ 0 by construction), under a name that says so; the result is `prediction`.
  iso["nominal_after"] = report::iso_json(r.iso_after);
  iso["nominal_after_meaning"] = report::kNominalAfterMeaning;
  iso["largest_abs_deviation_um"] = {{"before", r.largest_before_um}, {"nominal_after", r.largest_after_um}};
  iso["warnings"] = nlohmann::json::array();
  add_warning(iso, compensation_made_worse(grinding::largest_abs_deviation_um(r.before), grinding::largest_abs_deviation_um(r.after)));
  if (r.prediction) {
    iso["prediction"] = report::prediction_json(*r.prediction);
    iso["improvement"] = report::improvement_json(*r.prediction); // from the medians; none without a prediction
    write_prediction(dir, *r.prediction);
    add_warning(iso, prediction_made_worse(*r.prediction));
  }
  return iso;
}

} // namespace

nlohmann::json write_data_files(const fs::path& dir, const std::string& scene_file, const workbench::Workbench& wb,
                                const pipeline::PipelineResult& r) {
  grinding::write_topology_csv(dir / "topology_before.csv", r.before);
  grinding::write_topology_csv(dir / "topology_after.csv", r.after);
  grinding::write_traces_csv(dir / "traces_before.csv", r.before);
  grinding::write_traces_csv(dir / "traces_after.csv", r.after);
  r.corrections->write_csv(dir / "corrections.csv");
  const nlohmann::json iso = iso_file(dir, wb, r);
  output::write_text_atomically(dir / "iso1328.json", iso.dump(2) + "\n");
  if (r.measurement) { // what `compare` and `diagnose` write, from the same computations (README, "Outputs")
    const auto& m = *r.measurement;
    report::write_residuals_csv(dir / "residuals.csv", m.points, m.before);
    output::write_text_atomically(dir / "compare.json", report::compare_json(scene_file, m.file, m.points, m.before).dump(2) + "\n");
    output::write_text_atomically(
        dir / "diagnosis.json",
        diagnosis::diagnosis_json(scene_file, m.file, m.diagnosis, diagnosis::mean_allowance_offset_um(wb.setup.geometry())).dump(2) + "\n");
  }
  // Only an accepted explanation is added (docs/diagnosis.md: not ambiguous, no value at the end of its range).
  // As `diagnose` writes it (commands/measured.cpp): the fit's uncertainty, or its posterior's value sets.
  if (r.measurement && r.measurement->diagnosis.chosen && !r.measurement->diagnosis.withheld) {
    const auto& d = r.measurement->diagnosis;
    const auto identified = diagnosis::identified_effects(d, *d.chosen);
    diagnosis::write_scene_with_effects(scene_file, identified.effects,
                                        diagnosis::identification_comments(*d.chosen, r.measurement->file),
                                        dir / "scene_with_effect.yaml", identified.uncertainties, identified.correlation,
                                        d.chosen->changes, d.chosen->change_sd,
                                        diagnosis::change_identification_comments(*d.chosen, r.measurement->file),
                                        identified.draws, d.chosen->chain);
  }
  return iso;
}

void set_measurement(pipeline::PipelineOptions& po, const workbench::Workbench& wb, const std::string& measured,
                     const KlingelnbergFlags& mka) {
  po.measured_file = measured_of(wb, measured);
  refuse_mka_flags_without_export(po.measured_file, mka);
  po.measurement_format = mka.options;
  po.measured_against = measured_against(wb, po.measured_file, mka);
}

ReportJob run_report_job(const workbench::Workbench& wb, pipeline::PipelineOptions po, const std::string& scene_file,
                         const fs::path& dir, double max_time_s) {
  print_pipeline_estimate(wb, po);
  StageProgress progress(po, max_time_s);
  BeforeFigures before(po, wb, dir);
  ReportJob job;
  job.result = pipeline::run_pipeline(wb, po);
  progress.finish();
  if (job.result.measurement)
    for (const auto& w : job.result.measurement->warnings) say("geartopo: warning: " + w);
  job.iso = write_data_files(dir, scene_file, wb, job.result); // the page names them (corrections.csv …)
  job.figures = report::write_report(dir, wb, job.result, {}, before.take());
  return job;
}

void print_pipeline_estimate(const workbench::Workbench& wb, const pipeline::PipelineOptions& po) {
  const auto& grid = wb.scene.grid;
  const auto& teeth = po.teeth.empty() ? grid.teeth : po.teeth;
  const long long flanks = 2LL * static_cast<long long>(teeth.empty() ? wb.setup.geometry().teeth() : teeth.size());
  const long long per_flank = static_cast<long long>(grid.rows) * grid.cols + grid.profile_points + grid.helix_points;
  print_work_estimate(flanks * per_flank, flanks, po.method == grinding::Method::Exact, 2);
}

BeforeFigures::BeforeFigures(pipeline::PipelineOptions& po, const workbench::Workbench& wb, fs::path dir)
    : dir_(std::move(dir)) {
  po.before_ready = [this, &wb, dir = dir_](const pipeline::PipelineResult& r) {
    auto before = std::make_shared<pipeline::PipelineResult>(); // a copy: the pipeline's result moves on
    before->before = r.before;
    before->iso_before = r.iso_before;
    before->largest_before_um = r.largest_before_um;
    figures_ = std::async(std::launch::async, [&wb, dir, before] { return report::render_before_figures(wb, *before, dir); });
  };
}

BeforeFigures::~BeforeFigures() {
  if (!figures_.valid()) return; // taken: the report has them
  try {
    figures_.get();
  } catch (...) { // drawing failed too: the job's own error is the one to report
  }
}

std::vector<report::Figure> BeforeFigures::take() {
  return figures_.valid() ? figures_.get() : std::vector<report::Figure>{};
}

StageProgress::StageProgress(pipeline::PipelineOptions& po, double max_time_s) {
  po.stage = [this, &po, max_time_s](const std::string& stage, long long size) { start_stage(po, max_time_s, stage, size); };
  po.progress = [this](long long done, long long total) {
    if (simulation_) simulation_->flank_done(done, total);
    else if (progress_) progress_->update(done, total);
  };
  if (po.prediction) {
    po.prediction->on_sample_done = [this](long long done, long long total) {
      if (watch_) watch_->sample_done(done, total);
    };
    po.prediction->on_prepared = [this] {
      if (watch_) watch_->prepared();
    };
  }
}

void StageProgress::start_stage(const pipeline::PipelineOptions& po, double max_time_s, const std::string& stage,
                                long long size) {
  finish();
  const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - job_start_).count();
  if (stage == pipeline::kPredictionStage)
    watch_ = std::make_unique<MonteCarloWatch>(size, po.prediction ? po.prediction->threads : 0,
                                               std::max(1e-3, max_time_s - spent),
                                               "compensate --shard i/n on several machines and geartopo merge",
                                               po.prediction && po.prediction->adaptive_tolerance_um > 0.0);
  else if (size > 0 && stage.starts_with("simulate"))
    simulation_ = std::make_unique<SimulationWatch>(stage, size, 0, max_time_s, job_start_,
                                                    "a coarser grid (measurement.rows/cols) or fewer --teeth, or raise "
                                                    "--max-time-s");
  else
    progress_ = std::make_unique<Progress>(stage, size, stage == pipeline::kDiagnoseStage ? "candidate fits" : "flanks");
}

void StageProgress::finish() {
  watch_.reset();
  simulation_.reset();
  progress_.reset();
}

} // namespace geartopo::app
