// geartopo report / run: what the two commands that run the whole pipeline share — the files they read and write,
// the data files, the figures of the gear before compensation drawn while the pipeline goes on, and the progress of
// its stages.
#pragma once

#include "app/measurement_options.hpp"
#include "app/work_estimates.hpp"

#include "geartopo/files/output_folder.hpp"
#include "geartopo/pipeline/pipeline.hpp"
#include "geartopo/report/figures.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <future>
#include <memory>
#include <string>
#include <vector>

namespace geartopo::workbench {
struct Workbench;
}

namespace geartopo::app {

/// The measurement a job reads: `option` (--measured) when given, else the scene's measurement.measured.
std::string measured_of(const workbench::Workbench& wb, const std::string& option);

/// What `report` and `run` read and always write (the figures and the files of a measurement are checked as they are
/// written).
output::RunFiles report_files(const std::string& scene, const std::string& measured);

/// Writes the data files and returns iso1328.json's content (run --json prints it with the measurement's verdict).
nlohmann::json write_data_files(const std::filesystem::path& dir, const std::string& scene_file,
                                const workbench::Workbench& wb, const pipeline::PipelineResult& r);

/// The measurement options of a whole-pipeline job into `po`: the file (--measured, else the scene's), the
/// Klingelnberg reader's options (refused without an export) and what the file is measured against.
void set_measurement(pipeline::PipelineOptions& po, const workbench::Workbench& wb, const std::string& measured,
                     const KlingelnbergFlags& mka);

/// What a report job wrote: the pipeline's result, iso1328.json's content and the report's figures.
struct ReportJob {
  pipeline::PipelineResult result;
  nlohmann::json iso;
  std::vector<report::Figure> figures;
};

/// The job `run` and `report` share, into `dir` (an open OutputFolder's): the work estimate, the stages' progress,
/// the figures of the gear before compensation drawn while the pipeline goes on, the pipeline, the measurement's
/// warnings on stderr, the data files and the report. `po` is a copy: the job installs its progress and figure
/// callbacks into it.
ReportJob run_report_job(const workbench::Workbench& wb, pipeline::PipelineOptions po, const std::string& scene_file,
                         const std::filesystem::path& dir, double max_time_s);

/// Before the job: its two simulations (the gear before and after compensation) at the calibrated rate, when large
/// (print_work_estimate).
void print_pipeline_estimate(const workbench::Workbench& wb, const pipeline::PipelineOptions& po);

/// Draws the report's figures of the gear before compensation on another thread as soon as the pipeline has them
/// (PipelineOptions::before_ready), so that they render while the pipeline compensates, predicts and diagnoses: both
/// cores busy. Installs its callback into `po`, which must not outlive it; take() waits for the figures (and rethrows
/// what drawing them threw).
class BeforeFigures {
public:
  BeforeFigures(pipeline::PipelineOptions& po, const workbench::Workbench& wb, std::filesystem::path dir);
  BeforeFigures(const BeforeFigures&) = delete; // the callback holds `this`
  BeforeFigures& operator=(const BeforeFigures&) = delete;
  /// When the job failed after the figures started (e.g. refused by --max-time-s at a later stage): waits for them.
  /// What they wrote is staged (output_folder.hpp) and goes with the failed run's staging folder; the files of that
  /// name in the folder are the earlier run's, which a failed run leaves as they were.
  ~BeforeFigures();
  std::vector<report::Figure> take();

private:
  std::filesystem::path dir_;
  std::future<std::vector<report::Figure>> figures_;
};

/// Progress of the pipeline's stages on stderr (a terminal, not --quiet; progress.hpp): the flanks of each
/// simulation after its measured work estimate (SimulationWatch), the prediction's samples after theirs
/// (MonteCarloWatch), the diagnosis's candidate fits. The whole job is refused when the time it has spent plus a
/// stage's estimate exceeds max_time_s (--max-time-s). Installs its callbacks into `po`, which must not outlive it.
class StageProgress {
public:
  StageProgress(pipeline::PipelineOptions& po, double max_time_s);
  StageProgress(const StageProgress&) = delete; // the callbacks hold `this`
  StageProgress& operator=(const StageProgress&) = delete;
  /// Clears the progress line (before the results are printed).
  void finish();

private:
  void start_stage(const pipeline::PipelineOptions& po, double max_time_s, const std::string& stage, long long size);

  std::chrono::steady_clock::time_point job_start_ = std::chrono::steady_clock::now();
  std::unique_ptr<Progress> progress_;
  std::unique_ptr<SimulationWatch> simulation_;
  std::unique_ptr<MonteCarloWatch> watch_;
};

} // namespace geartopo::app
