#include "setup_terms.hpp"

#include "geartopo/core/units.hpp"

#include <cmath>

namespace geartopo::diagnosis {

double um_per_urad(const gears::GearGeometry& g) {
  // r_b (mm) · cos β_b · 1e-6 rad/µrad · 1e3 µm/mm.
  return units::um_from_mm(0.5 * g.base_diameter_mm()) * std::cos(g.base_helix_angle()) * units::rad_from_urad(1.0);
}

double setup_offset_um(const gears::GearGeometry& g, Flank flank, const SetupTerms& terms) {
  return terms.thickness_um + side_sign(flank) * um_per_urad(g) * terms.rotation_urad;
}

SetupTermModel::SetupTermModel(const gears::GearGeometry& g, const std::vector<MeasuredPoint>& pts) {
  const Eigen::Index n = static_cast<Eigen::Index>(pts.size());
  bool left = false, right = false;
  for (const auto& p : pts) (p.flank == Flank::Right ? right : left) = true;
  const double turn_um = um_per_urad(g);
  S_.resize(n, left && right ? 2 : 1);
  for (Eigen::Index i = 0; i < n; ++i) {
    S_(i, 0) = 1.0;
    if (S_.cols() == 2) S_(i, 1) = side_sign(pts[static_cast<size_t>(i)].flank) * turn_um;
  }
  WS_ = S_;
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(WS_);
  Q_ = qr.householderQ() * Eigen::MatrixXd::Identity(n, S_.cols());
}

SetupTermModel::SetupTermModel(const gears::GearGeometry& g, const std::vector<MeasuredPoint>& pts, StrokeScatter scatter)
    : SetupTermModel(g, pts) {
  scatter_ = std::move(scatter);
  WS_ = scatter_->whiten(S_);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(WS_);
  Q_ = qr.householderQ() * Eigen::MatrixXd::Identity(S_.rows(), S_.cols());
}

Eigen::VectorXd SetupTermModel::remove(const Eigen::VectorXd& r) const {
  const Eigen::VectorXd w = whiten(r);
  return w - Q_ * (Q_.transpose() * w);
}

Eigen::VectorXd SetupTermModel::coefficients(const Eigen::VectorXd& r) const {
  return (WS_.transpose() * WS_).ldlt().solve(WS_.transpose() * whiten(r));
}

Eigen::VectorXd SetupTermModel::remove_shown(const Eigen::VectorXd& r) const {
  return scatter_ ? Eigen::VectorXd(r - S_ * coefficients(r)) : remove(r);
}

SetupTerms SetupTermModel::fit(const Eigen::VectorXd& r, double sigma_um) const {
  const Eigen::MatrixXd StS = WS_.transpose() * WS_;                  // count × count
  const Eigen::VectorXd beta = coefficients(r);                       // t (µm)[, ψ (µrad)]
  const Eigen::MatrixXd cov = sigma_um * sigma_um * StS.inverse();    // count × count
  SetupTerms s;
  s.thickness_um = beta(0);
  s.thickness_sd_um = std::sqrt(cov(0, 0));
  s.rotation_identified = S_.cols() == 2;
  if (s.rotation_identified) {
    s.rotation_urad = beta(1);
    s.rotation_sd_urad = std::sqrt(cov(1, 1));
  }
  return s;
}

} // namespace geartopo::diagnosis
