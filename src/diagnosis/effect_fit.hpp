// geartopo diagnosis, private — the fit of one set of effects to a residual (docs/diagnosis.md, "Which effect is
// missing", steps 1–3): multi-start Levenberg–Marquardt, the linearised covariance, widened by a profile-likelihood
// walk of every nonlinear parameter, and the scores (explained fraction, RMS, ΔBIC). Units: µm (residuals), each
// parameter in its own unit (its key).
#pragma once

#include "setup_terms.hpp"

#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/effect_contribution.hpp"

#include <map>
#include <string>
#include <vector>

namespace geartopo::diagnosis {

/// Σ r² (µm² for residuals in µm).
double sum_of_squares(const std::vector<double>& r);

/// Every k-th measured point (in the measurement's order: k-th along each trace or grid row), with what a fit needs
/// there: the points' contact state, the set-up terms and the residual at them. On a large measurement the multi-start
/// search of a fit runs on these points, and only the best start's solution is polished on all points (fit_effects).
struct FitSubsample {
  EffectContribution at;   ///< the state at the subsample's points
  SetupTermModel terms;    ///< the set-up terms at them (with the same stroke scatter, if any)
  std::vector<double> r0;  ///< the residual there (µm)
};

/// The subsample's stride k for n points (count): 1 (no subsample) when n ≤ most, else ⌈n / most⌉; most = 0: 1.
std::size_t subsample_stride(std::size_t n, std::size_t most);

/// Fits the effects `types` jointly to the residual r0 (µm, one value per point of `at_points`), their contribution being
/// their first-order deviation at the points (evaluated from the points' stored contact state, effect_contribution.hpp), together with the set-up terms (`setup`: projected out, so the effects
/// are judged on what the set-up terms cannot take; the baseline RSS₀ is that of r0 with them removed). Starts from every combination of the start values of the nonlinear
/// parameters and, when `warm` has values of a type (a previous single fit, each parameter in its own unit), also from
/// those; keeps the smallest RSS. The candidate's `significant` is left to the caller.
/// With a `subsample`, the starts are run on its points and the best of them (smallest RSS there) is the start of one
/// more Levenberg–Marquardt run on all points, whose solution is the fit: values, RSS, covariance and the
/// profile-likelihood walk all come from every point (docs/diagnosis.md, "Large measurements").
Candidate fit_effects(const grinding::GrindingSetup& setup, const EffectContribution& at_points,
                      const std::vector<double>& r0, const std::vector<std::string>& types,
                      const std::map<std::string, std::vector<double>>& warm, const SetupTermModel& setup_terms,
                      const DiagnoseOptions& options, const FitSubsample* subsample = nullptr);

} // namespace geartopo::diagnosis
