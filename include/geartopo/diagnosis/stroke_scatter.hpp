// geartopo diagnosis — the covariance of measured residuals when every stroke of the grinder scatters and the model's
// error map is known only to its stated uncertainty (docs/diagnosis.md, "Stroke-to-stroke scatter and the map's
// uncertainty"). Units: µm (residuals, sensitivities per one standard deviation), mm and rad (axis repeatability).
//
// A stroke grinds one tooth space; its five axis commands (the chain's own: X, Y, Z, A, C on the CFXZAY) are each off by
// a random δq_a ~ N(0, s_a²),
// constant over the stroke (ISO 230-2 repeatability R = 4 s, scene `machine.repeatability`). To first order the measured
// deviation at point i of space s then carries g_iᵀ ξ_s, ξ_s ~ N(0, I₅), with g_i (5) the deviation at i per one s_a
// of each axis (µm). The error map's components are each off by a constant of N(0, u_c²) (scene `machine.uncertainty`;
// or by z·u_c(p), z ~ N(0, 1), where the component's table has an uncertainty column;
// the same draw the Monte Carlo makes), common to every point: m_iᵀ η, η ~ N(0, I), m_i the deviation at i per one u_c.
// With probe noise σ the residual's covariance is
//     Σ = D + M Mᵀ,   D = blockdiag_s(σ² I + G_s G_sᵀ)       (G_s: the rows g_iᵀ of space s, n_s × 5; M: n × m)
// Generalised least squares minimises ‖W r‖² with W Σ Wᵀ = σ² I: per space, with G_s = U_s S_s V_sᵀ (thin SVD, rank ≤ 5),
// W_s = σ D_s^(−1/2) = I − U_s diag(1 − σ/√(σ² + s_k²)) U_sᵀ — O(n_s) in time and memory, where a dense n_s × n_s
// factor of D_s would need 80 GB for a scanned flank of 10⁵ points; then with M' = W_D M = U S Vᵀ (thin SVD), W_M = I − U diag(1 − σ/√(σ² + s_k²)) Uᵀ, W = W_M W_D (σ² I + M'M'ᵀ has the
// eigenvalues σ² + s_k² on U and σ² elsewhere). The whitened residual is white noise of σ, so every white-noise formula
// (σ̂² (JᵀJ)⁻¹, χ², BIC) holds for it.
#pragma once

#include "geartopo/compensation/chain_axes.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/machine/axis_pose.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <Eigen/Dense>

#include <functional>
#include <vector>

namespace geartopo::diagnosis {

using measurement::MeasuredPoint; ///< what diagnosis works on: measured points, read by the measurement library

/// g_i for every point (n × 5, µm): the first-order deviation at each point when its space's stroke is commanded off by
/// one standard deviation s_a of axis a (ISO 230-2 R/4) — the axes `axes` (the scene's chain's own in its pose order,
/// linear in mm, rotary in rad; default: the setting's, the CFXZAY's X, Y, Z, A, C). The model's process carries the
/// offsets (a correction constant over every stroke, in those axes, as the Monte Carlo's stroke offsets are); the
/// space of a point is the one that grinds its flank.
/// `keep_going` (may be empty): predict's Ctrl-C check, every 4096 points of each of the 6 predictions.
Eigen::MatrixXd stroke_sensitivity(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                                   const std::vector<MeasuredPoint>& points, const machine::Vector5d& repeatability_sd,
                                   const compensation::ChainAxes& axes = {}, int threads = 0,
                                   const std::function<void()>& keep_going = {});

/// m_i for every point (n × 43, µm): the first-order deviation at each point when one component of the scene's error
/// map is off by its standard uncertainty u_c (a constant along its axis, as the Monte Carlo draws it; u_c(p) from the
/// component's table column where it has one, ErrorSource::drawn); a column of zeros for a component whose u_c is 0.
/// `keep_going` (may be empty): predict's Ctrl-C check, every 4096 points of each of the up to 44 predictions.
Eigen::MatrixXd map_sensitivity(const workbench::Workbench& wb, const std::vector<MeasuredPoint>& points, int threads = 0,
                                const std::function<void()>& keep_going = {});

/// Σ = blockdiag_s(σ² I + G_s G_sᵀ) + M Mᵀ and its whitening W (W Σ Wᵀ = σ² I).
class StrokeScatter {
public:
  /// space: the space grinding each point (n); G: stroke_sensitivity (n × 5, µm); noise_um: σ > 0 (µm); M: a part
  /// common to all points (n × m, µm, e.g. map_sensitivity; empty: none).
  StrokeScatter(const std::vector<int>& space, const Eigen::MatrixXd& G, double noise_um,
                const Eigen::MatrixXd& M = Eigen::MatrixXd());

  /// W r (n, µm): white noise of σ when r ~ N(0, Σ).
  Eigen::VectorXd whiten(const Eigen::VectorXd& r) const;
  /// W X, column by column (n × m).
  Eigen::MatrixXd whiten(const Eigen::MatrixXd& X) const;
  /// Σ (n × n, µm²), dense: for checks.
  Eigen::MatrixXd covariance() const;
  double noise_um() const { return noise_um_; }
  Eigen::Index size() const { return n_; }

private:
  struct Block {
    std::vector<Eigen::Index> idx; ///< points of the space
    Eigen::MatrixXd G;             ///< n_s × 5: the rows g_iᵀ of the space, for covariance()
    Eigen::MatrixXd U;             ///< n_s × k: left singular vectors of G with non-negligible singular values
    Eigen::VectorXd shrink;        ///< k: 1 − σ/√(σ² + s_k²)
  };
  Eigen::MatrixXd whiten_blocks(const Eigen::MatrixXd& X) const; ///< W_D X

  std::vector<Block> blocks_;
  Eigen::MatrixXd U_;      ///< n × k: left singular vectors of W_D M with non-negligible singular values
  Eigen::VectorXd shrink_; ///< k: 1 − σ/√(σ² + s_k²)
  Eigen::MatrixXd M_;      ///< n × m, for covariance()
  double noise_um_ = 0.0;
  Eigen::Index n_ = 0;
};

} // namespace geartopo::diagnosis
