// geartopo diagnosis — covariance of residuals under stroke-to-stroke scatter and its whitening (stroke_scatter.hpp).
#include "geartopo/diagnosis/stroke_scatter.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/grinding/flank_deviation.hpp"

#include <fmt/format.h>

#include <map>
#include <stdexcept>

namespace geartopo::diagnosis {

Eigen::MatrixXd stroke_sensitivity(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                                   const std::vector<MeasuredPoint>& pts, const machine::Vector5d& repeatability_sd,
                                   int threads) {
  const auto n = static_cast<Eigen::Index>(pts.size());
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, 5); // n × 5, µm per s_a
  const auto base = predict(setup, model, pts, grinding::Method::Linear, threads);
  for (int a = 0; a < 5; ++a) {
    if (repeatability_sd(a) <= 0.0) continue;
    // The same offset s_a on every stroke: each point feels its own space's, which is all g_i needs. The first-order
    // model is linear in the offset, so the difference is the sensitivity itself, not a finite-difference estimate.
    std::vector<compensation::CorrectionRow> rows;
    for (int s = 1; s <= setup.geometry().teeth(); ++s) {
      compensation::CorrectionRow row;
      row.space = s;
      row.correction(a) = repeatability_sd(a);
      rows.push_back(row);
    }
    const compensation::CorrectionTable offsets(std::move(rows));
    const compensation::CompensatedProcess off(model, offsets);
    const auto moved = predict(setup, off, pts, grinding::Method::Linear, threads);
    for (Eigen::Index i = 0; i < n; ++i) G(i, a) = moved[static_cast<size_t>(i)] - base[static_cast<size_t>(i)];
  }
  return G;
}

StrokeScatter::StrokeScatter(const std::vector<int>& space, const Eigen::MatrixXd& G, double noise_um)
    : noise_um_(noise_um), n_(static_cast<Eigen::Index>(space.size())) {
  if (!(noise_um > 0.0)) throw std::invalid_argument(fmt::format("stroke scatter: noise σ = {} µm (must be > 0)", noise_um));
  if (G.rows() != n_) throw std::invalid_argument("stroke scatter: one row of sensitivities per point is needed");
  std::map<int, std::vector<Eigen::Index>> by_space;
  for (Eigen::Index i = 0; i < n_; ++i) by_space[space[static_cast<size_t>(i)]].push_back(i);
  for (auto& [s, idx] : by_space) {
    Block b;
    b.idx = std::move(idx);
    const auto m = static_cast<Eigen::Index>(b.idx.size());
    Eigen::MatrixXd Gs(m, G.cols()); // n_s × 5
    for (Eigen::Index k = 0; k < m; ++k) Gs.row(k) = G.row(b.idx[static_cast<size_t>(k)]);
    const Eigen::MatrixXd sigma = noise_um * noise_um * Eigen::MatrixXd::Identity(m, m) + Gs * Gs.transpose();
    b.L = sigma.llt().matrixL(); // positive definite: σ² I plus a Gram matrix
    blocks_.push_back(std::move(b));
  }
}

Eigen::MatrixXd StrokeScatter::whiten(const Eigen::MatrixXd& X) const {
  if (X.rows() != n_) throw std::invalid_argument("stroke scatter: whitening needs one row per point");
  Eigen::MatrixXd out(X.rows(), X.cols());
  for (const auto& b : blocks_) {
    const auto m = static_cast<Eigen::Index>(b.idx.size());
    Eigen::MatrixXd xs(m, X.cols());
    for (Eigen::Index k = 0; k < m; ++k) xs.row(k) = X.row(b.idx[static_cast<size_t>(k)]);
    const Eigen::MatrixXd ws = noise_um_ * b.L.triangularView<Eigen::Lower>().solve(xs); // σ L⁻¹ x
    for (Eigen::Index k = 0; k < m; ++k) out.row(b.idx[static_cast<size_t>(k)]) = ws.row(k);
  }
  return out;
}

Eigen::VectorXd StrokeScatter::whiten(const Eigen::VectorXd& r) const {
  return whiten(Eigen::MatrixXd(r)).col(0);
}

Eigen::MatrixXd StrokeScatter::covariance() const {
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n_, n_);
  for (const auto& b : blocks_) {
    const Eigen::MatrixXd sb = b.L * b.L.transpose();
    for (size_t j = 0; j < b.idx.size(); ++j)
      for (size_t k = 0; k < b.idx.size(); ++k)
        S(b.idx[j], b.idx[k]) = sb(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(k));
  }
  return S;
}

} // namespace geartopo::diagnosis
