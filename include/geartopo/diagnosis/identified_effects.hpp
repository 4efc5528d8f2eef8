// geartopo — the explanation diagnosis chose, as a scene carries it: the effects with their fitted values, each value's
// standard uncertainty and their correlation (docs/diagnosis.md, "Into the scene, with the fit's uncertainty"), so that
// a prediction (pipeline/monte_carlo.hpp) draws the effect within what the measurement left open. Units: each
// parameter's own (its key).
#pragma once

#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/scene/scene.hpp"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace geartopo::diagnosis {

struct IdentifiedEffects {
  std::vector<scene::EffectSpec> effects;        ///< the candidate's effects with their fitted values
  /// Per effect, per value (parameter order): the fit's standard uncertainty (from σ̂² = RSS/ν of the whitened
  /// residual, so already as wide as the residual demands), at most the parameter's allowed range; 0 for a value
  /// held fixed.
  std::vector<std::vector<double>> uncertainties;
  /// N × N over all the effects' values in order (unit-free): the fit's p × p correlation at the fitted values'
  /// slots, identity elsewhere.
  Eigen::MatrixXd correlation;
  /// Per effect: the posterior's equally likely value sets (sets × values, file units; Diagnosis::draws) when the
  /// candidate is the diagnosis's choice and its single values are not determined; 0 rows otherwise. An effect with
  /// sets has no uncertainty and no correlation here: the sets are its whole distribution (Scene::effect_draws).
  std::vector<Eigen::MatrixXd> draws;
  /// √max(1, χ²/ν) of the whitened residual after the fit (Diagnosis::chi2_after, chi2_dof), for the reader: how much
  /// more the residual is than the noise, scatter and map the fit was told of (Birge 1932). The uncertainties
  /// already contain it (σ̂² = RSS/ν), so it is not applied again.
  double birge_ratio = 1.0;
};

/// The candidate of a diagnosis `d` (usually *d.chosen) with its uncertainties and correlation.
IdentifiedEffects identified_effects(const Diagnosis& d, const Candidate& candidate);

/// The comment line each of the candidate's effects gets in the scene it is added to ("thermal_drift: identified by
/// geartopo diagnose from measured.csv (ΔBIC -123.4)"), `measured` naming the measurement.
std::vector<std::string> identification_comments(const Candidate& candidate, const std::string& measured);
/// The same for its changed machine components (one per Candidate::changes), naming its equivalence class.
std::vector<std::string> change_identification_comments(const Candidate& candidate, const std::string& measured);

} // namespace geartopo::diagnosis
