// geartopo — the main job's computations, once: simulate the gear, evaluate it (ISO 1328-1), compensate it, and,
// when there is a measurement, compare and diagnose. Figures, the HTML report and the data files are written from
// the result. Units: µm, mm.
#pragma once

#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/workbench/workbench.hpp"
#include "geartopo/compensation/compensator.hpp"
#include "geartopo/compensation/correction_table.hpp"
#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::pipeline {

struct MeasurementResult {
  std::string file;
  std::vector<measurement::MeasuredPoint> points;
  diagnosis::Comparison before;             ///< against the scene's model
  diagnosis::Diagnosis diagnosis;
  std::optional<diagnosis::Comparison> after; ///< against the model with the chosen effect(s) added
  std::vector<std::string> warnings;        ///< the reader's (blocks of an export it did not use, …)
};

struct PipelineResult {
  std::vector<grinding::FlankTopology> before, after; ///< all teeth, grid + traces (exact)
  workbench::IsoResult iso_before, iso_after;
  std::unique_ptr<compensation::CorrectionTable> corrections;
  double largest_before_um = 0.0, largest_after_um = 0.0;
  std::optional<MeasurementResult> measurement;
  /// The after-state as a distribution (monte_carlo.hpp): the nominal `after` above is what the model promises itself
  /// (≈ 0 by construction), this is what a machine known only within its uncertainties would grind.
  std::optional<MonteCarloSummary> prediction;
};

/// The names of PipelineOptions::stage whose size is not in flanks.
inline constexpr const char* kPredictionStage = "predict (Monte Carlo)"; ///< size: samples
inline constexpr const char* kDiagnoseStage = "diagnose";                ///< progress: candidate fits

/// What the main job does, as `geartopo run`'s flags choose it (defaults: the scene's grid, every tooth, the flank
/// method at a 2 mm step, the noise estimated from the residual).
struct PipelineOptions {
  grinding::Method method = grinding::Method::Exact; ///< simulation of the topology (exact envelope or first order)
  std::vector<int> teeth;                            ///< empty: the scene's measurement.teeth (empty there: all)
  compensation::Method compensation = compensation::Method::Flank;
  double step_mm = 2.0;                              ///< correction table spacing along each stroke
  double noise_um = 0.0;                             ///< probe noise σ of the measurement; 0: estimated
  std::string measured_file;                         ///< empty: no comparison or diagnosis
  measurement::KlingelnbergOptions measurement_format; ///< how a Klingelnberg export is read (--mka-*)
  /// What a measured file without design_um is measured from (--measured-against, measurement.measured_against).
  measurement::MeasuredAgainst measured_against = measurement::MeasuredAgainst::as_file;
  /// How the ISO 1328-1 values are reported (default: the standard's transverse direction, docs/iso1328.md).
  workbench::IsoOptions iso;
  /// With it (samples ≥ 1, one shard), the compensated gear is also predicted by Monte Carlo (monte_carlo.hpp).
  std::optional<MonteCarloOptions> prediction;
  /// Told when a stage starts ("simulate", "compensate", "simulate compensated", "predict (Monte Carlo)", "compare",
  /// "diagnose"), with the stage's size: flanks of a simulation, samples of the prediction, 0 when not known in
  /// advance; for progress display only.
  std::function<void(const std::string& stage, long long size)> stage;
  /// (done, total) within the current stage: flanks of a simulation (grinding::SimulationOptions::progress),
  /// candidates of the diagnosis (diagnosis::DiagnoseOptions::on_candidate_fitted). The prediction's samples are
  /// told through prediction->on_sample_done.
  std::function<void(long long, long long)> progress;
  /// Called once, on the calling thread, as soon as the gear before compensation is simulated and evaluated, with the
  /// result so far: `before`, `iso_before` and `largest_before_um` set, nothing else. A report copies what it needs
  /// and draws it on another thread while the pipeline compensates, predicts and diagnoses (`geartopo run`).
  std::function<void(const PipelineResult& before_only)> before_ready;
};

PipelineResult run_pipeline(const workbench::Workbench& wb, const PipelineOptions& options);

/// The defaults with a measurement (tests, benchmarks).
PipelineResult run_pipeline(const workbench::Workbench& wb, const std::string& measured_file);

/// "7×9": the topological grid's rows × columns as simulated (the scene's measurement.rows, cols).
std::string grid_label(const PipelineResult& r);

} // namespace geartopo::pipeline
