#include "geartopo/diagnosis/levenberg_marquardt.hpp"

#include "geartopo/core/parallel.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <vector>

namespace geartopo::diagnosis {
namespace {

// J (n × p) is written in place and `known` (n, a closed-form column) reused: at 10⁶ residuals a fresh J is tens of
// MB, and the kernel's zeroing of its new pages cost more than filling it (perf, docs/performance.md).
void jacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
              const Eigen::VectorXd& r0, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
              const JacobianColumn& column, Eigen::MatrixXd& J, Eigen::VectorXd& known) {
  J.resize(r0.size(), x.size()); // n × p; a no-op after the first call
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    if (lo(j) == hi(j)) { // held fixed (a profile-likelihood refit): no step can move it, so no prediction for it
      J.col(j).setZero();
      continue;
    }
    if (column && column(x, j, known)) {
      J.col(j) = known;
      continue;
    }
    double h = 1e-4 * std::max(1.0, std::abs(x(j)));
    Eigen::VectorXd xp = x;
    if (xp(j) + h > hi(j)) h = -h; // stay inside the box
    xp(j) += h;
    J.col(j) = (f(xp) - r0) / h;
  }
}

// Rows per block of the normal equations: big enough that a block's p × p product is worth a task, small enough
// that 10⁵ rows make a dozen tasks. Fixed, so the association of the sums never depends on the thread count.
constexpr Eigen::Index kRowsPerBlock = 8192;

} // namespace

NormalEquations normal_equations(const Eigen::MatrixXd& J, const Eigen::VectorXd& r, int threads) {
  const Eigen::Index n = J.rows(), p = J.cols();
  const int blocks = static_cast<int>((n + kRowsPerBlock - 1) / kRowsPerBlock);
  std::vector<NormalEquations> part(static_cast<size_t>(blocks));
  geartopo::parallel_for(blocks, threads, [&](int b) {
    const Eigen::Index begin = b * kRowsPerBlock, rows = std::min(kRowsPerBlock, n - begin);
    const auto Jb = J.middleRows(begin, rows); // rows × p
    part[static_cast<size_t>(b)] = {Jb.transpose() * Jb, Jb.transpose() * r.segment(begin, rows)};
  });
  NormalEquations sum{Eigen::MatrixXd::Zero(p, p), Eigen::VectorXd::Zero(p)};
  for (const auto& q : part) { // in block order
    sum.JtJ += q.JtJ;
    sum.Jtr += q.Jtr;
  }
  return sum;
}

LmResult levenberg_marquardt(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x0,
                             const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, int max_iterations,
                             const JacobianColumn& column, int threads) {
  LmResult res;
  res.x = x0.cwiseMax(lo).cwiseMin(hi);
  Eigen::VectorXd r = f(res.x);
  res.rss = r.squaredNorm();
  double lambda = 1e-3;
  Eigen::MatrixXd J;     // n × p
  Eigen::VectorXd known; // n
  jacobian(f, res.x, r, lo, hi, column, J, known);
  for (int it = 0; it < max_iterations; ++it) {
    res.iterations = it + 1;
    const NormalEquations ne = normal_equations(J, r, threads);
    const Eigen::MatrixXd& A = ne.JtJ;
    const Eigen::VectorXd& g = ne.Jtr;
    bool improved = false;
    for (int tries = 0; tries < 12 && !improved; ++tries) {
      Eigen::MatrixXd M = A;
      M.diagonal() += lambda * (A.diagonal().array() + 1e-12).matrix();
      const Eigen::VectorXd step = M.ldlt().solve(-g);
      const Eigen::VectorXd x_new = (res.x + step).cwiseMax(lo).cwiseMin(hi);
      const Eigen::VectorXd r_new = f(x_new);
      const double rss_new = r_new.squaredNorm();
      if (std::isfinite(rss_new) && rss_new < res.rss) {
        const bool converged = (res.rss - rss_new) < 1e-10 * (1.0 + res.rss) || (x_new - res.x).norm() < 1e-9;
        res.x = x_new;
        r = r_new;
        res.rss = rss_new;
        lambda = std::max(lambda * 0.3, 1e-9);
        improved = true;
        jacobian(f, res.x, r, lo, hi, column, J, known);
        if (converged) {
          res.JtJ = normal_equations(J, r, threads).JtJ;
          return res;
        }
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) break;
  }
  res.JtJ = normal_equations(J, r, threads).JtJ;
  return res;
}

} // namespace geartopo::diagnosis
