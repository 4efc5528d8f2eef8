// geartopo diagnosis — covariance of residuals under stroke-to-stroke scatter and its whitening (stroke_scatter.hpp).
#include "geartopo/diagnosis/stroke_scatter.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/grinding/flank_deviation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace geartopo::diagnosis {

Eigen::MatrixXd stroke_sensitivity(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                                   const std::vector<MeasuredPoint>& pts, const machine::Vector5d& repeatability_sd,
                                   const compensation::ChainAxes& axes, int threads,
                                   const std::function<void()>& keep_going) {
  const auto n = static_cast<Eigen::Index>(pts.size());
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, 5); // n × 5, µm per s_a
  const auto base = predict(setup, model, pts, grinding::Method::Linear, threads, keep_going);
  for (int a = 0; a < 5; ++a) {
    if (repeatability_sd(a) <= 0.0) continue;
    // The same offset s_a of the chain's axis a on every stroke: each point feels its own space's, which is all g_i
    // needs. The first-order model is linear in the offset, so the difference is the sensitivity itself, not a
    // finite-difference estimate.
    std::vector<compensation::CorrectionRow> rows;
    for (int s = 1; s <= setup.geometry().teeth(); ++s) {
      compensation::CorrectionRow row;
      row.space = s;
      row.correction(a) = repeatability_sd(a);
      rows.push_back(row);
    }
    const compensation::CorrectionTable offsets(std::move(rows), axes);
    const compensation::CompensatedProcess off(model, offsets);
    const auto moved = predict(setup, off, pts, grinding::Method::Linear, threads, keep_going);
    for (Eigen::Index i = 0; i < n; ++i) G(i, a) = moved[static_cast<size_t>(i)] - base[static_cast<size_t>(i)];
  }
  return G;
}

Eigen::MatrixXd map_sensitivity(const workbench::Workbench& wb, const std::vector<MeasuredPoint>& pts, int threads,
                                const std::function<void()>& keep_going) {
  const auto n = static_cast<Eigen::Index>(pts.size());
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, machine::kComponentCount); // n × 43, µm per u_c
  const auto base = predict(wb.setup, wb.machine_process, pts, grinding::Method::Linear, threads, keep_going);
  const auto& u = wb.scene.machine.uncertainty.component_u;
  for (int c = 0; c < machine::kComponentCount; ++c) {
    // The scene's map with component c moved by one standard uncertainty, the Monte Carlo's draw at z = 1: u_c, or
    // u_c(p) from its table's column (the effects act on top of the map and cancel in the difference).
    const auto id = machine::component_at(c);
    std::vector<machine::ErrorSource> sources = wb.scene.machine.sources;
    const auto it = std::find_if(sources.begin(), sources.end(), [&](const auto& s) { return s.id() == id; });
    const bool column = it != sources.end() && it->has_uncertainty_column();
    if (!column && u[static_cast<size_t>(c)] <= 0.0) continue;
    if (it == sources.end()) sources.push_back(machine::ErrorSource::zero(id).drawn(1.0, u[static_cast<size_t>(c)]));
    else *it = it->drawn(1.0, u[static_cast<size_t>(c)]);
    const machine::MachineModel moved_model(wb.machine.strokes(), std::move(sources));
    const auto moved = workbench::make_machine_process(*wb.scene.machine.chain, moved_model, wb.scene.machine.datum_face_z_mm);
    const auto dev = predict(wb.setup, *moved, pts, grinding::Method::Linear, threads, keep_going);
    for (Eigen::Index i = 0; i < n; ++i) M(i, c) = dev[static_cast<size_t>(i)] - base[static_cast<size_t>(i)];
  }
  return M;
}

StrokeScatter::StrokeScatter(const std::vector<int>& space, const Eigen::MatrixXd& G, double noise_um,
                             const Eigen::MatrixXd& M)
    : M_(M), noise_um_(noise_um), n_(static_cast<Eigen::Index>(space.size())) {
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
    // D_s = σ² I + G_s G_sᵀ has the eigenvalues σ² + s_k² on G_s's left singular vectors and σ² elsewhere.
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Gs, Eigen::ComputeThinU);
    const Eigen::VectorXd& sv = svd.singularValues();
    Eigen::Index k = 0;
    while (k < sv.size() && sv(k) > 1e-9 * noise_um) ++k;
    b.U = svd.matrixU().leftCols(k);
    b.shrink = (1.0 - noise_um / (noise_um * noise_um + sv.head(k).array().square()).sqrt()).matrix();
    b.G = std::move(Gs);
    blocks_.push_back(std::move(b));
  }
  if (M.size() == 0) return;
  if (M.rows() != n_) throw std::invalid_argument("stroke scatter: one row of the common part per point is needed");
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(whiten_blocks(M), Eigen::ComputeThinU);
  const Eigen::VectorXd& sv = svd.singularValues();
  Eigen::Index k = 0;
  while (k < sv.size() && sv(k) > 1e-9 * noise_um) ++k; // directions M does not reach need no correction
  U_ = svd.matrixU().leftCols(k);
  shrink_ = (1.0 - noise_um / (noise_um * noise_um + sv.head(k).array().square()).sqrt()).matrix();
}

Eigen::MatrixXd StrokeScatter::whiten(const Eigen::MatrixXd& X) const {
  Eigen::MatrixXd out = whiten_blocks(X);
  if (U_.cols() > 0) out -= U_ * (shrink_.asDiagonal() * (U_.transpose() * out));
  return out;
}

Eigen::MatrixXd StrokeScatter::whiten_blocks(const Eigen::MatrixXd& X) const {
  if (X.rows() != n_) throw std::invalid_argument("stroke scatter: whitening needs one row per point");
  Eigen::MatrixXd out(X.rows(), X.cols());
  for (const auto& b : blocks_) {
    const auto m = static_cast<Eigen::Index>(b.idx.size());
    Eigen::MatrixXd xs(m, X.cols());
    for (Eigen::Index k = 0; k < m; ++k) xs.row(k) = X.row(b.idx[static_cast<size_t>(k)]);
    const Eigen::MatrixXd ws = xs - b.U * (b.shrink.asDiagonal() * (b.U.transpose() * xs)); // σ D_s^(−1/2) x
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
    const Eigen::MatrixXd sb = noise_um_ * noise_um_ * Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(b.idx.size()),
                                                                                  static_cast<Eigen::Index>(b.idx.size())) +
                               b.G * b.G.transpose();
    for (size_t j = 0; j < b.idx.size(); ++j)
      for (size_t k = 0; k < b.idx.size(); ++k)
        S(b.idx[j], b.idx[k]) = sb(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(k));
  }
  if (M_.size() > 0) S += M_ * M_.transpose();
  return S;
}

} // namespace geartopo::diagnosis
