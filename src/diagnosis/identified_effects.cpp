// geartopo — the chosen explanation with its uncertainty, as a scene carries it (identified_effects.hpp).
#include "geartopo/diagnosis/identified_effects.hpp"

#include "geartopo/effects/registry.hpp"
#include "geartopo/machine/kinematic_chain.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace geartopo::diagnosis {

namespace {

/// The posterior's value sets in place of the Gaussian of the effects they draw (Diagnosis::draws): the fit's σ of a
/// value that is not determined spans far beyond anything physical (±491 µm, ±64 633 s on the demo), and a Gaussian
/// held in the allowed range then predicts gears the measurement excludes.
void with_posterior_sets(const Diagnosis& d, const Candidate& candidate, IdentifiedEffects& out) {
  if (!d.draws || !d.chosen || d.chosen->effects.size() != candidate.effects.size()) return;
  for (size_t e = 0; e < candidate.effects.size(); ++e)
    if (d.chosen->effects[e].type != candidate.effects[e].type || d.chosen->effects[e].values != candidate.effects[e].values)
      return; // another candidate than the one drawn
  out.draws = d.draws->values;
  Eigen::Index first = 0;
  for (size_t e = 0; e < out.effects.size(); ++e) {
    const auto n = static_cast<Eigen::Index>(out.effects[e].values.size());
    if (e < out.draws.size() && out.draws[e].rows() > 0) {
      std::fill(out.uncertainties[e].begin(), out.uncertainties[e].end(), 0.0);
      out.correlation.middleRows(first, n).setZero();
      out.correlation.middleCols(first, n).setZero();
      out.correlation.block(first, first, n, n).setIdentity();
    }
    first += n;
  }
}

} // namespace

IdentifiedEffects identified_effects(const Diagnosis& d, const Candidate& candidate) {
  IdentifiedEffects out;
  out.effects = candidate.effects;
  out.birge_ratio = d.chi2_dof > 0.0 ? std::sqrt(std::max(1.0, d.chi2_after / d.chi2_dof)) : 1.0;
  // Each value's slot among all the effects' values, and which of them the fit moved (Candidate::correlation's order).
  std::vector<Eigen::Index> fitted_slot;
  Eigen::Index values = 0;
  for (size_t e = 0; e < out.effects.size(); ++e) {
    const auto params = effects::make_effect(out.effects[e].type)->parameters();
    std::vector<double> us(out.effects[e].values.size(), 0.0);
    for (size_t v = 0; v < params.size(); ++v) {
      if (e < candidate.parameters.size())
        for (const auto& p : candidate.parameters[e])
          if (p.key == params[v].key && p.fitted) {
            // The fit's σ already carries the residual: it is √(σ̂² (JᵀJ)⁻¹) with σ̂² = RSS/ν of the whitened
            // residual, i.e. (χ²/ν)·σ² (fit_effects) — multiplying by the Birge ratio again would count it twice.
            // At most the parameter's whole allowed range: wider says nothing a draw could use, and the scene
            // reader refuses it (an undetermined direction of the fit can be far wider).
            us[v] = std::min(p.uncertainty, params[v].hi - params[v].lo);
            fitted_slot.push_back(values + static_cast<Eigen::Index>(v));
          }
    }
    values += static_cast<Eigen::Index>(out.effects[e].values.size());
    out.uncertainties.push_back(std::move(us));
  }
  out.correlation = Eigen::MatrixXd::Identity(values, values);
  if (candidate.correlation.rows() == static_cast<Eigen::Index>(fitted_slot.size()))
    for (size_t a = 0; a < fitted_slot.size(); ++a)
      for (size_t b = 0; b < fitted_slot.size(); ++b)
        if (a != b)
          out.correlation(fitted_slot[a], fitted_slot[b]) =
              candidate.correlation(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
  with_posterior_sets(d, candidate, out);
  return out;
}

std::vector<std::string> identification_comments(const Candidate& candidate, const std::string& measured) {
  std::vector<std::string> comments;
  for (const auto& e : candidate.effects)
    comments.push_back(fmt::format("{}: identified by geartopo diagnose from {} (ΔBIC {:.1f})", e.type, measured,
                                   candidate.delta_bic));
  return comments;
}

std::vector<std::string> change_identification_comments(const Candidate& candidate, const std::string& measured) {
  std::vector<std::string> comments;
  for (const auto& c : candidate.changes)
    comments.push_back(fmt::format("{} {}: identified by geartopo diagnose from {} (ΔBIC {:.1f}){}",
                                   machine::info(candidate.chain, c.component).name, c.law_name(), measured,
                                   candidate.delta_bic,
                                   candidate.equivalent.empty()
                                       ? std::string()
                                       : fmt::format("; equivalent on the measured flanks: {}",
                                                     fmt::join(candidate.equivalent, ", "))));
  return comments;
}

} // namespace geartopo::diagnosis
