// geartopo diagnosis — the covariance of measured residuals when every stroke of the grinder scatters (docs/diagnosis.md,
// "Stroke-to-stroke scatter"). Units: µm (residuals, sensitivities per one standard deviation of scatter), mm and rad
// (axis repeatability).
//
// A stroke grinds one tooth space; its five axis commands X, Y, Z, A, C are each off by a random δq_a ~ N(0, s_a²),
// constant over the stroke (ISO 230-2 repeatability R = 4 s, scene `machine.repeatability`). To first order the measured
// deviation at point i of space s then carries g_iᵀ ξ_s, ξ_s ~ N(0, I₅), with g_i (5) the deviation at i per one s_a
// of each axis (µm). With probe noise σ the residual's covariance is block diagonal, one block per space:
//     Σ_s = σ² I + G_s G_sᵀ                    (n_s × n_s; G_s: the rows g_iᵀ of the space's points, n_s × 5)
// Generalised least squares minimises ‖W r‖² with W_s = σ L_s⁻¹, L_s L_sᵀ = Σ_s (Cholesky): W Σ Wᵀ = σ² I, so the
// whitened residual is white noise of σ and every white-noise formula (σ̂² (JᵀJ)⁻¹, χ², BIC) holds for it.
#pragma once

#include "geartopo/diagnosis/measured_points.hpp"
#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/machine/axis_pose.hpp"

#include <Eigen/Dense>

#include <vector>

namespace geartopo::diagnosis {

/// g_i for every point (n × 5, µm): the first-order deviation at each point when its space's stroke is commanded off by
/// one standard deviation s_a of axis a (X, Y, Z in mm, A, C in rad; ISO 230-2 R/4). The model's process carries the
/// offsets (a correction constant over every stroke); the space of a point is the one that grinds its flank.
Eigen::MatrixXd stroke_sensitivity(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                                   const std::vector<MeasuredPoint>& points, const machine::Vector5d& repeatability_sd,
                                   int threads = 0);

/// Σ = σ² I + Σ_s G_s G_sᵀ (block diagonal by space) and its whitening W (W Σ Wᵀ = σ² I).
class StrokeScatter {
public:
  /// space: the space grinding each point (n); G: stroke_sensitivity (n × 5, µm); noise_um: σ > 0 (µm).
  StrokeScatter(const std::vector<int>& space, const Eigen::MatrixXd& G, double noise_um);

  /// W r (n, µm): white noise of σ when r ~ N(0, Σ).
  Eigen::VectorXd whiten(const Eigen::VectorXd& r) const;
  /// W X, column by column (n × m).
  Eigen::MatrixXd whiten(const Eigen::MatrixXd& X) const;
  /// Σ (n × n, µm²), dense: for checks and small problems.
  Eigen::MatrixXd covariance() const;
  double noise_um() const { return noise_um_; }
  Eigen::Index size() const { return n_; }

private:
  struct Block {
    std::vector<Eigen::Index> idx; ///< points of the space
    Eigen::MatrixXd L;             ///< n_s × n_s, lower Cholesky factor of Σ_s
  };
  std::vector<Block> blocks_;
  double noise_um_ = 0.0;
  Eigen::Index n_ = 0;
};

} // namespace geartopo::diagnosis
