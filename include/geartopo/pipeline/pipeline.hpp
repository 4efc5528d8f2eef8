// geartopo — the main job's computations, once: simulate the gear, evaluate it (ISO 1328-1), compensate it, and,
// when there is a measurement, compare and diagnose. Figures, the HTML report and the data files are written from
// the result. Units: µm, mm.
#pragma once

#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/workbench/workbench.hpp"
#include "geartopo/compensation/correction_table.hpp"
#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::pipeline {

struct MeasurementResult {
  std::string file;
  std::vector<diagnosis::MeasuredPoint> points;
  diagnosis::Comparison before;             ///< against the scene's model
  diagnosis::Diagnosis diagnosis;
  std::optional<diagnosis::Comparison> after; ///< against the model with the chosen effect(s) added
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

/// With `prediction` set (and its samples ≥ 1, one shard), the compensated gear is also predicted by Monte Carlo.
PipelineResult run_pipeline(const workbench::Workbench& wb, const std::string& measured_file,
                            const std::optional<MonteCarloOptions>& prediction = std::nullopt);

/// "7×9": the topological grid's rows × columns as simulated (the scene's measurement.rows, cols).
std::string grid_label(const PipelineResult& r);

} // namespace geartopo::pipeline
