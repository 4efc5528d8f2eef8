// geartopo diagnosis — how each named pattern changes from tooth to tooth on one side: constant, a difference (two
// teeth), linear in tooth number, once per revolution or irregular, by χ²/F tests (docs/residual-patterns.md,
// section 2). Units: µm, µm per tooth, rad.
#pragma once

#include "geartopo/diagnosis/residuals/flank_patterns.hpp"

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::diagnosis {

enum class TrendKind {
  Constant,          ///< no change beyond the standard errors
  Difference,        ///< two teeth only, significantly different
  Linear,            ///< linear in tooth number
  OncePerRevolution, ///< c + A cos(θ_j − φ), θ_j = 2π (j − 1)/z
  Irregular          ///< varies beyond the standard errors, but neither trend is significant
};
std::string_view to_string(TrendKind k);

/// How one named pattern changes with tooth number. Fields that do not apply to the number of teeth stay 0/false.
struct PatternTrend {
  NamedPattern pattern = NamedPattern::Offset;
  TrendKind kind = TrendKind::Constant;
  std::size_t teeth = 0;
  Estimate mean_um;              ///< inverse-variance weighted mean
  double chi2_constant = 0.0;    ///< Σ ((y_j − mean)/s_j)² of the constant model
  int tooth_a = 0, tooth_b = 0;  ///< two teeth: lower and higher tooth number
  Estimate difference_um;        ///< two teeth: y_b − y_a
  Estimate slope_um_per_tooth;   ///< ≥ 3 teeth: weighted linear fit against tooth number
  bool linear_significant = false;
  bool sinusoid_fitted = false;  ///< ≥ 3 teeth whose angles determine c, a, b
  Estimate amplitude_um;         ///< A ≥ 0
  Estimate phase_rad;            ///< φ ∈ [0, 2π): the tooth angle where the pattern is largest
  double max_at_tooth = 0.0;     ///< 1 + φ z/(2π) (fractional tooth number)
  bool sinusoid_significant = false;
  bool scatter_beyond_model = false; ///< residual χ² of the chosen model still exceeds its 1 − p quantile
  std::string sentence;
};

struct TrendOptions {
  double significance_sigmas = 3.0; ///< k: tests at the two-sided normal tail p = erfc(k/√2) (0.27 % for k = 3)
};

struct SideTrends {
  Flank side = Flank::Right;
  int teeth_in_gear = 0;
  std::vector<int> teeth;             ///< ascending
  std::array<PatternTrend, 6> trends; ///< indexed like kNamedPatterns
};

/// Trends of the six named patterns over the given flanks (all of one side, distinct teeth in 1..teeth_in_gear, at
/// least 2). Throws std::invalid_argument otherwise, or for teeth_in_gear < 2 or non-finite/zero standard errors.
SideTrends fit_tooth_trends(std::span<const FlankPatterns> flanks, int teeth_in_gear, const TrendOptions& options = {});

} // namespace geartopo::diagnosis
