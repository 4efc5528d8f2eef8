// geartopo — measured − model: residuals at every measured point, their statistics, the named patterns of each flank,
// how the patterns change from tooth to tooth, and the regions where the model fails (docs/diagnosis.md).
// Units: µm, mm.
#pragma once

#include "geartopo/diagnosis/decision.hpp"

#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/diagnosis/residuals/failing_regions.hpp"
#include "geartopo/diagnosis/residuals/flank_patterns.hpp"
#include "geartopo/diagnosis/residuals/line_noise.hpp"
#include "geartopo/diagnosis/residuals/residual_summary.hpp"
#include "geartopo/diagnosis/residuals/tooth_trends.hpp"
#include "geartopo/diagnosis/residual_follows.hpp"
#include "geartopo/gears/involute_helicoid.hpp"
#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::diagnosis {

using measurement::MeasuredPoint; ///< what diagnosis works on: measured points, read by the measurement library

/// Where every measured point went: read = used + outside_evaluation_range + duplicates. The reader's own omissions
/// (undefined values, an export's points off the flank) have no residual and are counted beside them. Every count, RMS
/// and extreme that compare prints or writes is over the `used` points (docs/residual-patterns.md, "Counts").
struct PointCounts {
  std::size_t read = 0;                     ///< points the reader returned (residuals.csv has one row each)
  std::size_t used = 0;                     ///< inside the evaluation ranges L_α × L_β, first at their position
  std::size_t outside_evaluation_range = 0; ///< beyond L_α or L_β by more than 1 µm
  std::size_t duplicates = 0;               ///< a second point at a position (within 1 nm) of its flank: left out
  std::size_t undefined_values = 0;         ///< left out by the reader: the export's undefined value
  std::size_t off_flank_points = 0;         ///< left out by the reader: off the active flank
};

/// A flank's profile and helix lines where they cross (line_crossings): their differences, profile − helix (µm).
struct LineAgreement {
  int tooth = 1;
  Flank side = Flank::Right;
  std::size_t crossings = 0;
  double mean_difference_um = 0.0, max_abs_difference_um = 0.0;
  bool disagree = false; ///< max |difference| above 4σ√2 and 0.1 µm: the lines cannot both be right
  std::string sentence;  ///< set when they disagree
};

/// What a finding on a flank whose lines disagree says of itself (Comparison::disputed_sign).
inline constexpr const char* kDisputedSignNote =
    " — rests on a disputed sign: this flank's profile and helix lines disagree where they cross (the warning)";

struct Comparison {
  std::vector<double> model_um, residual_um;             ///< per measured point (model at the mean allowance)
  double allowance_offset_um = 0.0;                      ///< the model's nominal flank: mean_allowance_offset_um
  double noise_um = 0.0;
  bool noise_estimated = false;
  std::string noise_source;                              ///< how σ was estimated ("" when given)
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
  PointCounts counts;
  std::vector<LineAgreement> line_agreement;             ///< flanks with crossing dense profile and helix lines
  /// Per flank: its profile and helix lines disagree where they cross (LineAgreement::disagree), so its patterns and
  /// failing regions rest on a disputed sign rule or registration; its regions' sentences and the printed patterns
  /// end with kDisputedSignNote.
  std::vector<bool> disputed_sign;
  std::vector<std::size_t> flank_duplicates;             ///< per flank: duplicate positions left out
  /// The measurement looks evaluated against the drawing though read as against the bare involute: diagnose's first
  /// record (Reason::reference_in_doubt), said by compare too. None otherwise.
  std::optional<Decision> reference_in_doubt;
};

/// A measurement nobody said the reference of (MeasuredPoint::reference_declared false) whose residual (µm, one per
/// point) is largely minus the scene's design: the record diagnose's verdict opens with (docs/modifications.md,
/// "Measurements against the design"). None when the reference was said, or the design does not explain it.
std::optional<Decision> reference_in_doubt(const gears::GearGeometry& g, const std::vector<MeasuredPoint>& points,
                                           const std::vector<double>& residual_um, double noise_um);

/// The residual (µm, one per point) grouped by measured flank, ordered by tooth then left before right, each with the
/// ISO evaluation ranges; point_index (when given) receives each flank's indices into `points`. A point at the position
/// (ξ and z within 1 nm) of an earlier point of its flank is a duplicate: left out, counted in `duplicates` per flank.
std::vector<FlankResiduals> flank_residuals(const gears::EvaluationRanges& ranges, const std::vector<MeasuredPoint>& points,
                                            const std::vector<double>& residual_um,
                                            std::vector<std::vector<size_t>>* point_index = nullptr,
                                            std::vector<std::size_t>* duplicates = nullptr);

/// "479 measured points read: 463 used (inside the evaluation ranges), 16 outside the evaluation ranges, 0 duplicate
/// positions; left out by the reader: 1 undefined value, 0 points off the flank": the same sentence on the console and
/// in compare.json.
std::string describe_point_counts(const PointCounts& counts);

/// noise_um ≤ 0: estimated from the measured lines' own point-to-point scatter (estimate_noise_um). `read` is what the
/// reader left out (for the counts). `keep_going` (may be empty) is called between the steps and before each flank's
/// patterns (10⁶ points take seconds): a Ctrl-C check that may throw to stop, as DiagnoseOptions::keep_going.
Comparison compare(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                   const std::vector<MeasuredPoint>& points, double noise_um, const measurement::ReadCounts& read = {},
                   const std::function<void()>& keep_going = {});

} // namespace geartopo::diagnosis
