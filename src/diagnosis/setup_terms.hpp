// geartopo diagnosis, private — the set-up terms of a measurement (docs/diagnosis.md, "Set-up terms"): what every real
// measurement carries that is not physics of the grinding process, fitted as nuisance parameters in the baseline and
// in every candidate so that no effect can win by absorbing them.
//   thickness t (µm): the same normal offset on every flank, plus material positive (the tooth ground thicker or
//                     thinner than the nominal: infeed, wheel dressed over- or undersize, thickness allowance);
//   rotation ψ (µrad): the gear's angular registration on the measuring machine, a rigid turn about its axis. Turning
//                     by +ψ moves every right flank (facing +θ) into the space and every left flank out of it, along
//                     the flank normal by r_b·cos β_b·ψ (the involute helicoid's normal offset for a turn).
// So the terms at point i are t + σ_i·r_b·cos β_b·ψ, σ = +1 right, −1 left flank. With one flank side only, t and ψ
// cannot be told apart: ψ is dropped and t takes both.
#pragma once

#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/gears/gear_geometry.hpp"

#include <Eigen/Dense>

#include <vector>

namespace geartopo::diagnosis {

/// Normal offset (µm) per µrad of rigid turn: r_b·cos β_b (the involute helicoid's offset for a turn).
double um_per_urad(const gears::GearGeometry& g);

/// The set-up terms' normal offset (µm) at a point of a flank: t + σ·r_b·cos β_b·ψ (σ = +1 right, −1 left).
double setup_offset_um(const gears::GearGeometry& g, Flank flank, const SetupTerms& terms);

class SetupTermModel {
public:
  SetupTermModel(const gears::GearGeometry& g, const std::vector<MeasuredPoint>& points);

  /// r minus its least-squares fit by the set-up terms: what effects are judged on (n, µm).
  Eigen::VectorXd remove(const Eigen::VectorXd& r) const;
  /// The fitted terms of r with standard uncertainties for a residual noise of sigma_um (µm).
  SetupTerms fit(const Eigen::VectorXd& r, double sigma_um) const;
  /// Number of set-up terms fitted: 2, or 1 when only one flank side is measured.
  int count() const { return static_cast<int>(S_.cols()); }

private:
  Eigen::MatrixXd S_;  ///< n × count: columns 1 (µm per µm of t) and σ_i r_b cos β_b (µm per µrad of ψ)
  Eigen::MatrixXd Q_;  ///< n × count: orthonormal basis of the columns' span
};

} // namespace geartopo::diagnosis
