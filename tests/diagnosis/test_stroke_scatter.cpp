// Stroke-to-stroke scatter and a common model uncertainty: the residual covariance Σ = σ² I + Σ_s G_s G_sᵀ + M Mᵀ and
// generalised least squares through its whitening. Truths from outside the code: Σ written out densely here and
// inverted by Eigen (the textbook GLS covariance (Xᵀ Σ⁻¹ X)⁻¹), and the empirical spread of a linear fit over 400
// residuals drawn here with the standard library's generator: per space one offset of five "axes" through G, one
// offset of three "map components" through M common to all points, plus white noise.
#include "geartopo/diagnosis/stroke_scatter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

using namespace geartopo;

namespace {

constexpr int kScatterSpaces = 12, kScatterPointsPerSpace = 6;
constexpr double kScatterNoiseUm = 0.3;

/// A space per point (spaces listed out of order, as measured points are) and its within-flank position in [−1, 1].
struct ScatterLayout {
  std::vector<int> space;
  Eigen::VectorXd position; // n
};

ScatterLayout scatter_layout() {
  ScatterLayout l;
  const int n = kScatterSpaces * kScatterPointsPerSpace;
  l.position.resize(n);
  for (int i = 0; i < n; ++i) {
    const int k = i % kScatterPointsPerSpace;
    l.space.push_back(1 + (i / kScatterPointsPerSpace * 5) % kScatterSpaces); // 1, 6, 11, 4, 9, …: a permutation of 1…12
    l.position(i) = -1.0 + 2.0 * k / (kScatterPointsPerSpace - 1);
  }
  return l;
}

/// Sensitivities (n × 5, µm per standard deviation of each axis): an offset, a slope, a curvature along the flank and
/// two mixtures — the shapes axis offsets leave on a flank, sizes of the order of the noise.
Eigen::MatrixXd scatter_sensitivity(const ScatterLayout& l) {
  const auto n = static_cast<Eigen::Index>(l.space.size());
  Eigen::MatrixXd G(n, 5);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = l.position(i);
    G.row(i) << 0.8, 0.4 * x, 0.3 * x * x, 0.5 - 0.2 * x, 0.1 + 0.6 * x;
  }
  return G;
}

/// A part common to all points (n × 3, µm per standard uncertainty): an offset growing along the grinding order (the
/// kind of pattern a drift also makes), a flank slope, and a once-around pattern.
Eigen::MatrixXd common_sensitivity(const ScatterLayout& l) {
  const auto n = static_cast<Eigen::Index>(l.space.size());
  Eigen::MatrixXd M(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double s = l.space[static_cast<size_t>(i)];
    M.row(i) << 0.05 * s, 0.3 * l.position(i), 0.5 * std::sin(2.0 * 3.14159265358979 * s / kScatterSpaces);
  }
  return M;
}

/// Σ written out: σ² on the diagonal plus g_iᵀ g_j for points of one space plus m_iᵀ m_j for all (n × n, µm²).
Eigen::MatrixXd scatter_sigma_dense(const ScatterLayout& l, const Eigen::MatrixXd& G, const Eigen::MatrixXd& M) {
  const auto n = static_cast<Eigen::Index>(l.space.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) {
      if (l.space[static_cast<size_t>(i)] == l.space[static_cast<size_t>(j)]) S(i, j) = G.row(i).dot(G.row(j));
      if (i == j) S(i, j) += kScatterNoiseUm * kScatterNoiseUm;
      S(i, j) += M.row(i).dot(M.row(j));
    }
  return S;
}

/// The model: a drift along the grinding order (space number / 12, µm per unit) and a slope along the flank (µm).
Eigen::MatrixXd scatter_design(const ScatterLayout& l) {
  const auto n = static_cast<Eigen::Index>(l.space.size());
  Eigen::MatrixXd X(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) X.row(i) << l.space[static_cast<size_t>(i)] / double(kScatterSpaces), l.position(i);
  return X;
}

} // namespace

TEST(StrokeScatter, WhiteningTurnsTheWrittenOutCovarianceIntoWhiteNoise) {
  const auto l = scatter_layout();
  const Eigen::MatrixXd G = scatter_sensitivity(l);
  const Eigen::MatrixXd M = common_sensitivity(l);
  const diagnosis::StrokeScatter scatter(l.space, G, kScatterNoiseUm, M);
  const Eigen::MatrixXd Sigma = scatter_sigma_dense(l, G, M);
  EXPECT_LT((scatter.covariance() - Sigma).cwiseAbs().maxCoeff(), 1e-12);
  // W Σ Wᵀ = σ² I: whiten the columns of Σ, then the rows of the result.
  const Eigen::MatrixXd WS = scatter.whiten(Sigma);
  const Eigen::MatrixXd WSWt = scatter.whiten(Eigen::MatrixXd(WS.transpose()));
  const auto n = static_cast<Eigen::Index>(l.space.size());
  EXPECT_LT((WSWt - kScatterNoiseUm * kScatterNoiseUm * Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(StrokeScatter, GeneralisedLeastSquaresCovarianceMatchesTheSpreadOfDrawnFits) {
  const auto l = scatter_layout();
  const Eigen::MatrixXd G = scatter_sensitivity(l);
  const Eigen::MatrixXd M = common_sensitivity(l);
  const diagnosis::StrokeScatter scatter(l.space, G, kScatterNoiseUm, M);
  const Eigen::MatrixXd X = scatter_design(l);
  const auto n = static_cast<Eigen::Index>(l.space.size());

  // The fit's covariance through the whitening, against the textbook (Xᵀ Σ⁻¹ X)⁻¹ with Σ inverted densely.
  const Eigen::MatrixXd WX = scatter.whiten(X);
  const Eigen::Matrix2d cov_gls = kScatterNoiseUm * kScatterNoiseUm * (WX.transpose() * WX).inverse();
  const Eigen::MatrixXd Sigma = scatter_sigma_dense(l, G, M);
  const Eigen::Matrix2d cov_textbook = (X.transpose() * Sigma.inverse() * X).inverse();
  EXPECT_LT((cov_gls - cov_textbook).cwiseAbs().maxCoeff(), 1e-9 * cov_textbook.cwiseAbs().maxCoeff());

  // Draws: y = X β + noise + per space G_s ξ_s + M η. The fitted β's empirical standard deviation must match √cov within
  // its sampling error (relative 1/√(2(M−1)) = 3.5 % for M = 400; 4 of them: 14 %).
  const Eigen::Vector2d beta{2.0, -1.0};
  std::mt19937_64 gen(15);
  std::normal_distribution<double> normal(0.0, 1.0);
  constexpr int kDraws = 400;
  Eigen::MatrixXd fits(kDraws, 2), ols_fits(kDraws, 2);
  for (int d = 0; d < kDraws; ++d) {
    std::vector<Eigen::Matrix<double, 5, 1>> xi(kScatterSpaces + 1);
    for (auto& v : xi)
      for (int a = 0; a < 5; ++a) v(a) = normal(gen);
    Eigen::Vector3d eta;
    for (int c = 0; c < 3; ++c) eta(c) = normal(gen);
    Eigen::VectorXd y = X * beta + M * eta;
    for (Eigen::Index i = 0; i < n; ++i)
      y(i) += kScatterNoiseUm * normal(gen) + G.row(i).dot(xi[static_cast<size_t>(l.space[static_cast<size_t>(i)])]);
    fits.row(d) = (WX.transpose() * WX).ldlt().solve(WX.transpose() * scatter.whiten(y)).transpose();
    ols_fits.row(d) = (X.transpose() * X).ldlt().solve(X.transpose() * y).transpose();
  }
  const double tol = 4.0 / std::sqrt(2.0 * (kDraws - 1));
  for (int j = 0; j < 2; ++j) {
    const double mean = fits.col(j).mean();
    const double sd = std::sqrt((fits.col(j).array() - mean).square().sum() / (kDraws - 1));
    const double predicted = std::sqrt(cov_gls(j, j));
    EXPECT_NEAR(sd / predicted, 1.0, tol) << "parameter " << j;
    EXPECT_NEAR(mean, beta(j), 4.0 * predicted / std::sqrt(double(kDraws))) << "parameter " << j; // unbiased
    // Why it matters: ordinary least squares with white-noise σ claims far less than its estimates really scatter.
    const double ols_mean = ols_fits.col(j).mean();
    const double ols_sd = std::sqrt((ols_fits.col(j).array() - ols_mean).square().sum() / (kDraws - 1));
    const double ols_claimed = kScatterNoiseUm * std::sqrt((X.transpose() * X).inverse()(j, j));
    EXPECT_GT(ols_sd, 2.0 * ols_claimed) << "parameter " << j;
    std::cout << "parameter " << j << ": GLS sd " << sd << " (predicted " << predicted << "), OLS sd " << ols_sd
              << " (white-noise claim " << ols_claimed << ")\n";
  }
}
