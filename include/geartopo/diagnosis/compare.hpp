// geartopo — measured − model: residuals at every measured point, their statistics, the named patterns of each flank,
// how the patterns change from tooth to tooth, and the regions where the model fails (docs/diagnosis.md).
// Units: µm, mm.
#pragma once

#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/diagnosis/residuals/failing_regions.hpp"
#include "geartopo/diagnosis/residuals/flank_patterns.hpp"
#include "geartopo/diagnosis/residuals/residual_summary.hpp"
#include "geartopo/diagnosis/residuals/tooth_trends.hpp"
#include "geartopo/diagnosis/residual_follows.hpp"
#include "geartopo/gears/involute_helicoid.hpp"
#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"

#include <optional>
#include <string>
#include <vector>

namespace geartopo::diagnosis {

using measurement::MeasuredPoint; ///< what diagnosis works on: measured points, read by the measurement library

struct Comparison {
  std::vector<double> model_um, residual_um;             ///< per measured point (model at the mean allowance)
  double allowance_offset_um = 0.0;                      ///< the model's nominal flank: mean_allowance_offset_um
  double noise_um = 0.0;
  bool noise_estimated = false;
  std::vector<FlankResiduals> flanks;                    ///< one per measured flank (tooth, then left, right)
  std::vector<std::vector<size_t>> flank_point_index;    ///< flank → indices into the measured points
  std::vector<FlankPatterns> patterns;                   ///< per flank (empty entry: too few points to fit)
  std::vector<bool> has_patterns;
  std::vector<SideTrends> trends;                        ///< per side with ≥ 2 teeth
  std::vector<FailingRegion> regions;                    ///< every flank's regions
  ResidualSummary summary;
  /// What the residual follows: its dependence on each process variable of the points' generation (grinding time,
  /// stroke order, Z, C angle, wheel radius), strongest first (residual_follows.hpp). Empty with fewer than 4 points.
  ResidualFollows follows;
};

/// The residual (µm, one per point) grouped by measured flank, ordered by tooth then left before right, each with the
/// ISO evaluation ranges; point_index (when given) receives each flank's indices into `points`.
std::vector<FlankResiduals> flank_residuals(const gears::EvaluationRanges& ranges, const std::vector<MeasuredPoint>& points,
                                            const std::vector<double>& residual_um,
                                            std::vector<std::vector<size_t>>* point_index = nullptr);

/// noise_um ≤ 0: estimated (quadratic surface per flank).
Comparison compare(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                   const std::vector<MeasuredPoint>& points, double noise_um);

} // namespace geartopo::diagnosis
