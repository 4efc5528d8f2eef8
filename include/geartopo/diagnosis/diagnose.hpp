// geartopo — which physical effect is missing from a model, judged on measurements (docs/diagnosis.md).
//
// For every candidate effect of the library that the scene does not model, its parameters are fitted to the residual
// (measured − model) by Levenberg–Marquardt on the simulator: the effect's contribution at the measured points is its
// first-order deviation (superposed on the model's exact deviation — both are small). Each fit reports values with
// standard uncertainties, the fraction of the residual's sum of squares it explains, the RMS before and after, and
// ΔBIC = n ln(RSS/RSS₀) + p ln n against the model without it, so that a many-parameter effect does not win by
// over-fitting. Candidates are ranked by ΔBIC; an effect is significant when ΔBIC < −threshold. When the best one
// leaves more than 1.5× the noise (DiagnoseOptions::explained_noise_factor), pairs of significant effects are fitted
// jointly. Units: µm, and each parameter's
// own unit (its key).
#pragma once

#include "geartopo/diagnosis/measured_points.hpp"
#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/scene/scene.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::diagnosis {

struct FittedParameter {
  std::string key;           ///< with its unit, e.g. "x_growth_um"
  double value = 0.0;
  double uncertainty = 0.0;  ///< standard uncertainty (1σ); 0 for parameters held fixed
  bool fitted = true;
};

struct Candidate {
  std::vector<scene::EffectSpec> effects;               ///< one (or two, for a combination) with fitted values
  std::vector<std::vector<FittedParameter>> parameters; ///< per effect
  std::vector<std::string> explanations;                ///< one line of physics per effect
  double rms_before_um = 0.0, rms_after_um = 0.0;
  double explained_fraction = 0.0; ///< 1 − RSS/RSS₀
  double delta_bic = 0.0;
  bool significant = false;
  std::string name() const;        ///< "thermal_drift" or "thermal_drift + wheel_wear"
};

/// What diagnose does and when; the defaults are the documented behaviour (docs/diagnosis.md).
struct DiagnoseOptions {
  double noise_um = 0.0;            ///< probe noise σ (µm); ≤ 0: estimated from the residual (quadratic surface per flank)
  /// ΔBIC an effect must beat (unit-free, on the natural-log BIC scale): significant when ΔBIC < −threshold, and a pair
  /// must improve on the best single effect by as much again. 10 is "very strong" evidence (Kass & Raftery), so that
  /// a library effect is not named on data that only mildly prefer it.
  double bic_threshold = 10.0;
  std::vector<std::string> candidates; ///< effect types to try; empty: every library effect not in the scene
  int threads = 0;                  ///< threads of the predictions; 0: all hardware threads
  /// Fewest measured points (count) diagnose accepts: the noise estimate fits 6 terms per flank, and BIC with a
  /// handful of points rewards nothing.
  std::size_t min_points = 10;
  /// A residual counts as explained when its RMS is at most this multiple of the noise σ (unit-free). Above it, the
  /// best single effect is fitted jointly with each other significant one, and the verdict says part of the residual
  /// remains. 1.5: pure noise has RMS ≈ σ, and an estimated σ from a few flanks can be off by tens of per cent; a
  /// missing effect comparable to the noise still raises the RMS beyond it.
  double explained_noise_factor = 1.5;
  /// Significant single effects taken into pairs (count): the best with each of the next ones, up to this many in
  /// all. 4 (three pairs): each joint fit costs as much as several single fits, and an effect ranked below fourth has
  /// not explained enough alone to be the needed partner.
  std::size_t pair_candidates = 4;
  /// Ridge added to the diagonal of JᵀJ before inverting it for the covariance, relative to max(1, trace) (unit-free,
  /// parameters scaled by their typical size). 1e-12: negligible for identifiable parameters, but a direction the data
  /// cannot see gets a huge variance instead of a singular matrix or a false zero.
  double covariance_ridge = 1e-12;
  /// Profile-likelihood walk of a nonlinear parameter: the largest number of steps on each side (count), the step
  /// doubling from the linearised σ. 8 steps reach 2⁷ = 128 σ, beyond which the bound is a box limit anyway.
  int profile_walk_steps = 8;
  /// Smallest first step of that walk (unit-free, in units of the parameter's typical size): a parameter whose
  /// linearised σ is 0 still moves.
  double profile_min_step = 1e-6;
};

struct Diagnosis {
  int points = 0;
  double noise_um = 0.0;
  bool noise_estimated = false;
  double rms_before_um = 0.0;
  std::vector<Candidate> ranked;       ///< single effects, best ΔBIC first
  std::optional<Candidate> combination; ///< a significant pair, when one effect leaves too much
  std::optional<Candidate> chosen;      ///< what to add: the combination, else the best significant single effect
  std::vector<double> residual_before_um, residual_after_um; ///< per point (after: with `chosen`, exact simulation)
  std::string verdict;                  ///< one paragraph for people
};

/// `model` is what the scene models (geometric errors and the scene's own effects); `in_scene` its effect types.
Diagnosis diagnose(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                   const std::vector<MeasuredPoint>& points, const std::vector<std::string>& in_scene,
                   const DiagnoseOptions& options);

/// Noise σ (µm) estimated from residuals: a quadratic surface in (roll length, z) fitted per flank, the pooled
/// residual standard deviation. Flanks with fewer than 10 points are skipped; if none is left, 0.1 µm — a
/// conservative probe figure, so that no caller divides by or compares with a zero noise.
double estimate_noise_um(const std::vector<MeasuredPoint>& points, const std::vector<double>& residual_um);

} // namespace geartopo::diagnosis
