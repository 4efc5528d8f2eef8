// geartopo — a production series analysed (docs/series.md): per measured gear its ISO 1328-1 values and classes and
// its residual against the scene's model (and what its corrections should change in it), then each per-gear quantity over
// the series fitted with the across-series laws (drift_model.hpp), the next gear predicted and the gear at which the
// drawing's class is expected to be lost. Units: µm, s, h, strokes.
#pragma once

#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/series/drift_model.hpp"
#include "geartopo/series/series_file.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::series {

/// One measured gear's values.
struct GearValues {
  SeriesGear gear;
  std::optional<workbench::IsoResult> iso; ///< when its file holds profile and helix traces
  std::string iso_note;                    ///< why not, otherwise
  double mean_residual_um[2] = {0.0, 0.0}; ///< measured − model (without the gear's corrections), mean over the used
                                           ///< points of the left [0] and right [1] flanks
  double correction_effect_um[2] = {0.0, 0.0}; ///< the model with the gear's corrections − without, same means (0: none)
  std::size_t points[2] = {0, 0};          ///< used points per side
  double rms_residual_um = 0.0;            ///< over every used point
  double noise_um = 0.0;                   ///< probe noise estimated from the measured lines (compare's)
  double mean_grinding_time_s = 0.0;       ///< mean over the used points, from the job's start
  double mean_stroke = 0.0;                ///< mean place of their strokes in the job (0: the first stroke)
  int correction_set = 0;                  ///< 0: the first corrections (or none), +1 at each change
  /// The within-job effects: the gear's measurement through diagnose's pipeline (diagnosis::diagnose, as `geartopo
  /// diagnose` runs it) against the model it was ground with (the scene's, with its corrections), when the series asks
  /// for it (SeriesOptions::diagnose_gears, the series file's `diagnose_gears`); its per-point residuals dropped.
  std::optional<diagnosis::Diagnosis> diagnosis;
};

/// A per-gear quantity over the series, and what the across-series model says of it.
struct SeriesQuantity {
  std::string key;                ///< "mean_residual_left_um", "f_Halpha_m_left_um", "F_alpha_max_um", …
  std::string label;              ///< "mean residual, left flanks", "f_Hαm, left flanks", "F_α, worst flank", …
  std::optional<evaluation::Quantity> iso; ///< the ISO quantity whose tolerance applies (none for the residuals)
  std::optional<double> limit_um; ///< the drawing's class tolerance (|value| ≤ limit), when the scene gives the class
  std::vector<double> values_um;  ///< per gear
  double floor_um = 0.0;          ///< the least scatter the probe noise allows in this quantity
  std::optional<SeriesFit> fit;   ///< none with fewer than 3 gears
  std::optional<Predicted> next;  ///< the next gear
  std::optional<ClassLoss> loss;  ///< with a limit
};

/// Whether the quantity's limit holds on both sides (±limit: the slopes f_Hα, f_Hβ and the thickness allowance) rather
/// than 0 … limit (the quantities compared by size).
bool two_sided_limit(const SeriesQuantity& q);

struct SeriesOptions {
  int max_gears_ahead = 500; ///< how far class_loss looks
  /// Each gear diagnosed as `geartopo diagnose` does (GearValues::diagnosis): ~0.1 s per gear of 252 points, ~8 s per
  /// gear of 10⁵ points (docs/series.md). Either this or the series file's `diagnose_gears: true` turns it on.
  bool diagnose_gears = false;
  /// Called before each gear, between its steps, every 4096 lines of an export it reads and before each quantity's
  /// fit (20 gears of 10⁵ points take tens of seconds): a Ctrl-C check that may throw to stop, as
  /// grinding::SimulationOptions::keep_going. May be empty.
  std::function<void()> keep_going;
};

struct SeriesResult {
  SeriesSpec spec;
  std::vector<GearValues> gears;
  std::vector<GearState> states;  ///< what the laws see, per gear
  GearState next, step;           ///< the next gear's state and the step per gear after it (mean interval, strokes per gear)
  double strokes_per_gear = 0.0;
  std::optional<int> drawing_class;
  std::vector<SeriesQuantity> quantities;
};

/// One gear's values: its measurement read against the workbench's set-up, compared with the scene's model (ground
/// with `corrections` when given), evaluated to ISO 1328-1 when it holds traces.
/// `options`: keep_going as SeriesOptions'.
GearValues gear_values(const workbench::Workbench& wb, const SeriesGear& gear, const workbench::IsoOptions& iso = {},
                       const SeriesOptions& options = {});

/// The whole series. Throws InputError naming the file of a gear that cannot be read.
SeriesResult analyse_series(const SeriesSpec& spec, const workbench::Workbench& wb, const SeriesOptions& options = {});

/// The scene's strokes in one job (the strokes of its wheel path).
double strokes_per_gear(const workbench::Workbench& wb);

/// series.json: the per-gear values, each quantity's fit, prediction and class loss (units in the keys).
nlohmann::json series_json(const SeriesResult& r);
/// The console's summary: one line per gear, one paragraph per quantity whose law is not noise.
std::string series_text(const SeriesResult& r);

} // namespace geartopo::series
