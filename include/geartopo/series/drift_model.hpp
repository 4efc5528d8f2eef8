// geartopo — the across-series model: how one per-gear value (an ISO 1328-1 quantity, a flank's mean residual) moves
// from gear to gear through states that carry over between jobs (docs/series.md):
//
//   y_k = c + a (1 − e^(−t_k/τ))      thermal drift: the machine warming from the series start towards a steady state
//       + w S_k                       wheel wear: S_k strokes since the last dressing, reset to 0 by a re-dress
//       + Σ_j d_j [set_k = j]         a step each time the corrections changed (set 0: the first corrections or none)
//       + ε_k,  ε ~ N(0, s²)
//
// Laws are tried alone and in pairs, each kept only when an F-test against the smaller model rejects it at 1 % (divided
// by the number of laws tried at that step), then the smallest BIC wins. τ is found by profiling (log grid, then Brent); the covariance is s² (JᵀJ)⁻¹ with the full
// Jacobian (τ included). A value the series does not fix (τ at the search bound or σ_τ > τ, a law whose column does
// not vary) is marked "not determined". Plain data in, plain data out; units: µm, h, strokes.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace geartopo::series {

/// The states of one measured gear as the laws see them.
struct GearState {
  double time_h = 0.0;                 ///< since the series start, at the mean grinding time of its measured points
  double strokes_since_dressing = 0.0; ///< at the mean stroke of its measured points
  int correction_set = 0;              ///< 0 for the first corrections (or none), +1 at every change
};

enum class Law { ThermalDrift, WheelWear, CorrectionStep };
/// "thermal drift", "wheel wear", "correction step".
std::string to_string(Law law);

/// One parameter of a fit, with its standard uncertainty (1σ).
struct FittedParameter {
  std::string name; ///< "offset_um", "thermal_amplitude_um", "time_constant_h", "wear_um_per_stroke", "step_1_um", …
  double value = 0.0, sigma = 0.0;
  bool determined = true;   ///< false: the series does not fix it (see `why`)
  std::string why;          ///< why not determined
};

/// A model of the series: the laws it holds and its fit.
struct LawFit {
  std::vector<Law> laws; ///< empty: noise about a constant
  std::vector<FittedParameter> parameters;
  Eigen::MatrixXd covariance; ///< parameters × parameters, in their units
  double rss = 0.0;           ///< Σ (y − ŷ)², µm²
  double sigma_um = 0.0;      ///< s: the scatter from gear to gear left over (at least the floor)
  int n = 0, p = 0;           ///< gears and parameters
  double bic = 0.0;
  double f_statistic = 0.0, f_critical = 0.0; ///< against the model it extends (0 for noise)
  bool significant = false;                   ///< F above the critical value (1 % over the laws tried)
  double time_constant_h() const;             ///< NaN without thermal drift
  std::string name() const;                   ///< "noise only", "thermal drift + wheel wear", …
};

struct SeriesFit {
  LawFit chosen;
  std::vector<LawFit> tried;        ///< every model fitted, noise first
  std::vector<std::string> notes;   ///< laws the series cannot test ("wheel wear: no dressing information", …)
};

/// Which laws the series can test: wear needs the strokes to vary, a step needs ≥ 2 correction sets, thermal drift
/// needs ≥ 4 gears spread over time. `floor_um` (> 0): the least gear-to-gear scatter possible (the probe noise of the
/// mean), so that a perfect fit never reads as infinitely certain. Throws std::invalid_argument for fewer than 3
/// gears, sizes that differ or a value that is not finite.
SeriesFit fit_series(const std::vector<GearState>& states, const std::vector<double>& y_um, double floor_um);

/// The fit of a given set of laws (nullopt when there are too few gears for its parameters).
std::optional<LawFit> fit_laws(const std::vector<GearState>& states, const std::vector<double>& y_um,
                               const std::vector<Law>& laws, double floor_um);

/// A value predicted for a gear in the state `at`: median and 95 % interval (Student t with n − p degrees of freedom;
/// the gear-to-gear scatter plus the parameters' uncertainty to first order).
struct Predicted {
  double median_um = 0.0, sigma_um = 0.0, lower95_um = 0.0, upper95_um = 0.0;
};
Predicted predict(const LawFit& fit, const GearState& at);

/// When the value is expected to leave the class: |value| > limit (ISO 1328-1 tolerances are compared by their
/// absolute value). Found by stepping gear by gear from `next` with `step` added each time (no re-dress, the last
/// corrections) up to `max_gears` gears.
struct ClassLoss {
  bool already = false;          ///< the next gear's median is already outside
  std::optional<int> gears_median, gears_early, gears_late; ///< gears after the last measured one (1 = the next)
  std::optional<double> strokes_median, strokes_early, strokes_late; ///< strokes since dressing at those gears (the
                                                                     ///< states' strokes; analyse_series: at the job's start)
  std::optional<double> time_median_h, time_early_h, time_late_h;    ///< time since the series start (likewise)
};
/// early: the first gear whose 95 % interval reaches beyond the limit; median: the first whose median does; late: the
/// first whose whole interval lies beyond it.
ClassLoss class_loss(const LawFit& fit, const GearState& next, const GearState& step, double limit_um, int max_gears);

} // namespace geartopo::series
