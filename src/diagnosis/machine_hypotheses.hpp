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
/// rejected ones. Each Candidate has its `changes` (with change_sd) or its effect (one-sided wheel_flank_profile, or
/// wheel_profile_wear), the
/// description, ΔBIC against no hypothesis (set-up terms fitted in both), rms_before/after with the set-up removed,
/// and for the first its `equivalent` hypotheses.
/// `in_scene`: what the scene models already (effect types, changes as "E_AOA linear_in_time"): not proposed again, so
/// that the completed scene never lists a change twice.
std::vector<Candidate> fit_machine_hypotheses(const grinding::GrindingSetup& setup, const EffectContribution& at_points,
                                              const std::vector<double>& residual_um, const SetupTermModel& setup_terms,
                                              const DiagnoseOptions& options, const std::vector<std::string>& in_scene = {});

/// Whether c is a hypothesis beyond the library: one component change under its law, one wheel flank's profile
/// error (its wheel_flank_profile effect qualified "(left)" or "(right)"), or the wheel profile's wear
/// (wheel_profile_wear).
bool is_machine_hypothesis(const Candidate& c);

/// A hypothesis' first-order field at `at`'s points, linear in its coefficients: the columns fit_machine_hypotheses
/// fits, X (n × p; µm per mm or rad of the component, or per µm of a wheel flank's slope and crowning), and the
/// candidate's coefficients β (p; a once-per-revolution change as (a cos φ, a sin φ)): its field is X β (n, µm).
/// Throws std::invalid_argument for a candidate that is no machine hypothesis.
struct HypothesisField {
  Eigen::MatrixXd X;
  Eigen::VectorXd beta;
};
HypothesisField hypothesis_field(const grinding::GrindingSetup& setup, const EffectContribution& at, const Candidate& c,
                                 int threads = 0);

} // namespace geartopo::diagnosis
