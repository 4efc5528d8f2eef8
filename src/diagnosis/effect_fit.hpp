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

/// Fits the effects `types` jointly to the residual r0 (µm, one value per point of `at_points`), their contribution being
/// their first-order deviation at the points (evaluated from the points' stored contact state, effect_contribution.hpp), together with the set-up terms (`setup`: projected out, so the effects
/// are judged on what the set-up terms cannot take; the baseline RSS₀ is that of r0 with them removed). Starts from every combination of the start values of the nonlinear
/// parameters and, when `warm` has values of a type (a previous single fit, each parameter in its own unit), also from
/// those; keeps the smallest RSS. The candidate's `significant` is left to the caller.
Candidate fit_effects(const grinding::GrindingSetup& setup, const EffectContribution& at_points,
                      const std::vector<double>& r0, const std::vector<std::string>& types,
                      const std::map<std::string, std::vector<double>>& warm, const SetupTermModel& setup_terms,
                      const DiagnoseOptions& options);

} // namespace geartopo::diagnosis
