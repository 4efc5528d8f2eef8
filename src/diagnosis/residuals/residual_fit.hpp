// geartopo diagnosis, private to the residual analysis — what its sections share: refusing bad input, the in-range
// points of a flank with normalised coordinates, distinct positions, ordinary least squares and amplitude/phase of a
// cos/sin pair. Units: mm (ξ, z), µm (residuals, σ), rad.
#pragma once

#include "geartopo/diagnosis/residuals/flank_residuals.hpp"

#include <Eigen/Dense>

#include <cstddef>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::diagnosis::residuals {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;
inline constexpr std::size_t kLegendreTerms = 6; ///< 1, u, w, u·w, P2(u), P2(w)

/// Throws std::invalid_argument "<what> refused: <why>".
[[noreturn]] void refuse(std::string_view what, const std::string& why);

/// "tooth 3, right flank".
std::string flank_name(int tooth, Flank side);

/// In-range points of one flank with normalised coordinates.
struct Prepared {
  std::vector<std::size_t> index; ///< into FlankResiduals::points
  std::vector<double> xi, z, u, w, r;
  std::size_t outside = 0;
  std::size_t size() const { return index.size(); }
};

/// Checks the flank (tooth ≥ 1, finite non-empty ranges, finite points) and keeps its points inside the evaluation
/// ranges (with kRangeSlackMm); refuses a flank with no point in range.
Prepared prepare(const FlankResiduals& f, std::string_view what);

/// Refuses σ not finite or ≤ 0 (µm).
void check_noise(std::string_view what, double sigma);

/// Sorted distinct values (values closer than tol merge into the first of them).
std::vector<double> distinct(std::vector<double> v, double tol);

struct LsFit {
  Eigen::VectorXd coef;
  Eigen::MatrixXd cov_unit; ///< (AᵀA)⁻¹: covariance of coef per unit noise variance
  Eigen::VectorXd resid;
  double rss = 0.0;
};


/// Ordinary least squares of y (n) on A (n × p); nullopt when A does not have full column rank.
std::optional<LsFit> least_squares(const Eigen::MatrixXd& A, const Eigen::VectorXd& y);

/// Amplitude and phase of a cos + b sin = A cos(θ − φ), with standard errors from the 2 × 2 covariance of (a, b)
/// (delta method); φ ∈ [0, 2π).
void amplitude_phase(double a, double b, const Eigen::Matrix2d& cov, Estimate& amp, Estimate& phase);

/// "+1.23 µm".
std::string signed_um(double v, int decimals = 2);

} // namespace geartopo::diagnosis::residuals
