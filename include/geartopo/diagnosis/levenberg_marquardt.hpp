// geartopo — Levenberg–Marquardt for small nonlinear least-squares problems (a handful of parameters, hundreds of
// residuals), with box bounds and finite-difference Jacobians (or closed-form columns where the caller has them). Variables should be scaled to order one.
#pragma once

#include <Eigen/Core>

#include <functional>

namespace geartopo::diagnosis {

struct LmResult {
  Eigen::VectorXd x;   ///< solution
  double rss = 0.0;    ///< Σ r² at the solution
  Eigen::MatrixXd JtJ; ///< JᵀJ at the solution (p×p), for covariances
  int iterations = 0;
};

/// The normal equations' parts: JᵀJ (p × p) and Jᵀr (p) of a Jacobian J (n × p) and residual r (n).
struct NormalEquations {
  Eigen::MatrixXd JtJ; ///< p × p
  Eigen::VectorXd Jtr; ///< p
};

/// JᵀJ and Jᵀr summed over fixed blocks of rows in parallel (`threads`; 0: all hardware threads), the blocks' sums then
/// added in block order: the same bits at any thread count.
NormalEquations normal_equations(const Eigen::MatrixXd& J, const Eigen::VectorXd& r, int threads = 0);

/// Column j of the residual's Jacobian at x (n), written to `column`, when the caller knows it in closed form (a
/// parameter the residual is linear in); returns false to leave the column to finite differences.
using JacobianColumn = std::function<bool(const Eigen::VectorXd& x, Eigen::Index j, Eigen::VectorXd& column)>;

/// Minimises Σ r(x)² within lo ≤ x ≤ hi (clamped), from x0. Jacobian columns from `column` where it gives them, by
/// forward differences elsewhere; the normal equations on `threads` (normal_equations: the result does not depend on it).
LmResult levenberg_marquardt(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& residual,
                             const Eigen::VectorXd& x0, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                             int max_iterations = 60, const JacobianColumn& column = {}, int threads = 1);

} // namespace geartopo::diagnosis
