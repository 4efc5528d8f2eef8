// geartopo diagnosis, private — explanations beyond the library (docs/diagnosis.md, "Beyond the library"): every error
// component of the chain changed since the map was measured, under each law a machine element follows (constant,
// linear in time, approaching a steady state, once per C revolution), and a profile error of one wheel flank. Each is
// linear in its size (the steady state's τ and the revolution's phase by a grid and a sine/cosine pair), so every fit
// is a least-squares projection of the residual, with the set-up terms removed, onto the hypothesis' first-order
// columns at the points' stored generating poses (EffectContribution): 43 components × 4 laws in a fraction of a
// second on 10⁵ points. Units: µm, and each size's own unit.
#pragma once

#include "effect_fit.hpp"
#include "setup_terms.hpp"

#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/effect_contribution.hpp"

#include <Eigen/Dense>

#include <vector>

namespace geartopo::diagnosis {

/// Every hypothesis fitted to `residual_um` (measured − model, n), ranked: plausible ones by ΔBIC (best first), then the
/// rejected ones. Each Candidate has its `changes` (with change_sd) or its one-sided wheel_flank_profile effect, the
/// description, ΔBIC against no hypothesis (set-up terms fitted in both), rms_before/after with the set-up removed,
/// and for the first its `equivalent` hypotheses.
/// `in_scene`: what the scene models already (effect types, changes as "E_AOA linear_in_time"): not proposed again, so
/// that the completed scene never lists a change twice.
std::vector<Candidate> fit_machine_hypotheses(const grinding::GrindingSetup& setup, const EffectContribution& at_points,
                                              const std::vector<double>& residual_um, const SetupTermModel& setup_terms,
                                              const DiagnoseOptions& options, const std::vector<std::string>& in_scene = {});

} // namespace geartopo::diagnosis
