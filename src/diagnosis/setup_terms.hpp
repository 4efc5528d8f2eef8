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
// With stroke-to-stroke scatter declared (stroke_scatter.hpp) the terms are fitted by generalised least squares and
// `remove` returns the whitened remainder (W r minus its fit by W S): what every fit and test is judged on.
#pragma once

#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/stroke_scatter.hpp"
#include "geartopo/gears/gear_geometry.hpp"

#include <Eigen/Dense>

#include <optional>
#include <vector>

namespace geartopo::diagnosis {

/// Normal offset (µm) per µrad of rigid turn: r_b·cos β_b (the involute helicoid's offset for a turn).
double um_per_urad(const gears::GearGeometry& g);

/// The set-up terms' normal offset (µm) at a point of a flank: t + σ·r_b·cos β_b·ψ (σ = +1 right, −1 left).
double setup_offset_um(const gears::GearGeometry& g, Flank flank, const SetupTerms& terms);

class SetupTermModel {
public:
  SetupTermModel(const gears::GearGeometry& g, const std::vector<MeasuredPoint>& points);
  /// The same terms with the residual's stroke-to-stroke scatter: fits become generalised least squares.
  SetupTermModel(const gears::GearGeometry& g, const std::vector<MeasuredPoint>& points, StrokeScatter scatter);

  /// What effects are judged on (n, µm): r minus its least-squares fit by the set-up terms; with scatter, the whitened
  /// W r minus its fit by W S (white noise of σ when r is noise and scatter), whose squared norm is the GLS objective.
  Eigen::VectorXd remove(const Eigen::VectorXd& r) const;
  /// r minus its (generalised) least-squares fit by the set-up terms, not whitened: a residual to show (n, µm).
  Eigen::VectorXd remove_shown(const Eigen::VectorXd& r) const;
  /// The fitted terms of r (generalised least squares with scatter) with standard uncertainties for a (whitened)
  /// residual noise of sigma_um (µm).
  SetupTerms fit(const Eigen::VectorXd& r, double sigma_um) const;
  bool has_scatter() const { return scatter_.has_value(); }
  /// Number of set-up terms fitted: 2, or 1 when only one flank side is measured.
  int count() const { return static_cast<int>(S_.cols()); }

private:
  Eigen::VectorXd whiten(const Eigen::VectorXd& r) const { return scatter_ ? scatter_->whiten(r) : r; }
  Eigen::VectorXd coefficients(const Eigen::VectorXd& r) const; ///< count: the (generalised) least-squares fit of r

  Eigen::MatrixXd S_;  ///< n × count: columns 1 (µm per µm of t) and σ_i r_b cos β_b (µm per µrad of ψ)
  Eigen::MatrixXd WS_; ///< n × count: the columns whitened (= S_ without scatter)
  Eigen::MatrixXd Q_;  ///< n × count: orthonormal basis of WS_'s span
  std::optional<StrokeScatter> scatter_;
};

} // namespace geartopo::diagnosis
