// The Levenberg–Marquardt normal equations summed in parallel blocks (diagnosis/levenberg_marquardt.hpp) against the
// plain serial sums written here, and their independence of the thread count. Units: none (pure algebra).
#include "geartopo/diagnosis/levenberg_marquardt.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace geartopo;

namespace {

// A tall Jacobian (several blocks and a partial last one) of order-one entries with a spread of column scales, as a
// fit's scaled columns have.
Eigen::MatrixXd tall_jacobian(Eigen::Index rows, Eigen::Index cols, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  Eigen::MatrixXd J(rows, cols); // rows × cols
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) J(i, j) = std::pow(10.0, static_cast<double>(j % 3)) * unit(rng);
  return J;
}

// Σ_i J_ij J_ik and Σ_i J_ij r_i in long double, one row after another: the sum every blocked association must agree
// with to rounding. Bound: each of n ≈ 5·10⁴ products rounds at ε|J_ij J_ik|, so the double sums differ from the exact
// one by at most ≈ n·ε·Σ|J_ij J_ik| in the worst case; relative to Σ|J_ij J_ik| that is 1e-11 — the bound below.
TEST(NormalEquations, EqualTheSerialSumsToRounding) {
  const Eigen::Index n = 50'001, p = 6;
  const Eigen::MatrixXd J = tall_jacobian(n, p, 3);
  const Eigen::VectorXd r = tall_jacobian(n, 1, 4).col(0);
  const auto ne = diagnosis::normal_equations(J, r, 2);
  ASSERT_EQ(ne.JtJ.rows(), p);
  ASSERT_EQ(ne.Jtr.size(), p);
  for (Eigen::Index j = 0; j < p; ++j) {
    long double g = 0.0L, g_abs = 0.0L;
    for (Eigen::Index i = 0; i < n; ++i) g += static_cast<long double>(J(i, j)) * r(i), g_abs += std::abs(J(i, j) * r(i));
    EXPECT_LE(std::abs(ne.Jtr(j) - static_cast<double>(g)), 1e-11 * static_cast<double>(g_abs)) << "column " << j;
    for (Eigen::Index k = 0; k < p; ++k) {
      long double a = 0.0L, a_abs = 0.0L;
      for (Eigen::Index i = 0; i < n; ++i) a += static_cast<long double>(J(i, j)) * J(i, k), a_abs += std::abs(J(i, j) * J(i, k));
      EXPECT_LE(std::abs(ne.JtJ(j, k) - static_cast<double>(a)), 1e-11 * static_cast<double>(a_abs)) << j << ", " << k;
    }
  }
}

TEST(NormalEquations, AreTheSameBitsOnOneTwoAndThreeThreads) {
  const Eigen::MatrixXd J = tall_jacobian(40'000, 5, 5);
  const Eigen::VectorXd r = tall_jacobian(40'000, 1, 6).col(0);
  const auto one = diagnosis::normal_equations(J, r, 1), two = diagnosis::normal_equations(J, r, 2),
             three = diagnosis::normal_equations(J, r, 3);
  for (Eigen::Index j = 0; j < J.cols(); ++j) {
    EXPECT_EQ(one.Jtr(j), two.Jtr(j));
    EXPECT_EQ(one.Jtr(j), three.Jtr(j));
    for (Eigen::Index k = 0; k < J.cols(); ++k) {
      EXPECT_EQ(one.JtJ(j, k), two.JtJ(j, k));
      EXPECT_EQ(one.JtJ(j, k), three.JtJ(j, k));
    }
  }
}

// The minimiser itself on one and two threads, on a problem whose answer is known: a straight line through exact data
// (truth: the line's own coefficients), 30 000 residuals so that the normal equations span several blocks.
TEST(LevenbergMarquardt, FindsAKnownLineTheSameOnOneAndTwoThreads) {
  const Eigen::Index n = 30'000;
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0);
  const auto residual = [&](const Eigen::VectorXd& x) { return Eigen::VectorXd((0.7 + 2.5 * t.array()) - (x(0) + x(1) * t.array())); };
  const Eigen::Vector2d x0(0.0, 0.0), lo(-10.0, -10.0), hi(10.0, 10.0);
  const auto one = diagnosis::levenberg_marquardt(residual, x0, lo, hi, 60, {}, 1);
  const auto two = diagnosis::levenberg_marquardt(residual, x0, lo, hi, 60, {}, 2);
  EXPECT_NEAR(one.x(0), 0.7, 1e-8);
  EXPECT_NEAR(one.x(1), 2.5, 1e-8);
  EXPECT_EQ(one.x(0), two.x(0));
  EXPECT_EQ(one.x(1), two.x(1));
  EXPECT_EQ(one.rss, two.rss);
}

} // namespace
