// geartopo tests — tooth-to-tooth trends of the named patterns (docs/residual-patterns.md, section 2).
// Units: µm, µm per tooth, rad.
#include "diagnosis/residual_fixtures.hpp"

#include "geartopo/diagnosis/residuals/flank_patterns.hpp"
#include "geartopo/diagnosis/residuals/tooth_trends.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

using namespace geartopo::diagnosis;
using namespace geartopo::diagnosis::test;
using geartopo::Flank;

namespace {

// ----------------------------------------------------------------------------------------- 2. tooth trends

/// Fitted patterns of teeth `teeth` (right flanks, 7 × 9 grid, σ noise), the field of tooth j given by make(j).
std::vector<FlankPatterns> fit_teeth(const std::vector<int>& teeth, const std::function<Field(int)>& make,
                                     double sigma, std::uint64_t seed) {
  std::vector<FlankPatterns> out;
  for (int j : teeth)
    out.push_back(
        fit_flank_patterns(grid(7, 9, make(j), sigma, seed + static_cast<std::uint64_t>(j), j), with_noise(sigma)));
  return out;
}

const PatternTrend& trend_of(const SideTrends& t, NamedPattern p) {
  return t.trends[static_cast<std::size_t>(p)];
}

TEST(Trends, LinearTrendOverSixTeeth) {
  // Helix slope 2 + 0.8 (j − 1) µm over teeth 1..6 of 35; offset constant 1 µm.
  const double sigma = 0.5;
  const auto flanks = fit_teeth(
      {1, 2, 3, 4, 5, 6},
      [](int j) { return [j](double, double w) { return 1.0 + (2.0 + 0.8 * (j - 1)) * w / 2.0; }; }, sigma, 900);
  const auto t = fit_tooth_trends(flanks, 35);
  const PatternTrend& h = trend_of(t, NamedPattern::HelixSlope);
  EXPECT_EQ(h.kind, TrendKind::Linear) << h.sentence;
  EXPECT_NEAR(h.slope_um_per_tooth.value, 0.8, 3 * h.slope_um_per_tooth.standard_error);
  EXPECT_NE(h.sentence.find("per tooth"), std::string::npos) << h.sentence;
  const PatternTrend& o = trend_of(t, NamedPattern::Offset);
  EXPECT_EQ(o.kind, TrendKind::Constant) << o.sentence;
  EXPECT_NEAR(o.mean_um.value, 1.0, 3 * o.mean_um.standard_error);
  EXPECT_EQ(t.teeth, (std::vector<int>{1, 2, 3, 4, 5, 6}));
}

TEST(Trends, OncePerRevolutionSinusoidOverAllTeeth) {
  // Offset 1 + 2.5 cos(θ_j − 2.0) over all 35 teeth (an eccentric gear): largest at θ = 2 rad, tooth 1 + 2·35/2π.
  const int z = 35;
  const double sigma = 0.5, A = 2.5, phi = 2.0;
  std::vector<int> teeth;
  for (int j = 1; j <= z; ++j) teeth.push_back(j);
  const auto flanks = fit_teeth(
      teeth,
      [&](int j) {
        const double th = 2 * kPi * (j - 1) / z;
        return [=](double, double) { return 1.0 + A * std::cos(th - phi); };
      },
      sigma, 4000);
  const auto t = fit_tooth_trends(flanks, z);
  const PatternTrend& o = trend_of(t, NamedPattern::Offset);
  EXPECT_EQ(o.kind, TrendKind::OncePerRevolution) << o.sentence;
  EXPECT_NEAR(o.amplitude_um.value, A, 3 * o.amplitude_um.standard_error);
  EXPECT_NEAR(o.phase_rad.value, phi, 3 * o.phase_rad.standard_error);
  EXPECT_NEAR(o.max_at_tooth, 1.0 + phi * z / (2 * kPi), 0.5);
  EXPECT_NEAR(o.mean_um.value, 1.0, 3 * o.mean_um.standard_error);
  for (NamedPattern p : {NamedPattern::ProfileSlope, NamedPattern::HelixSlope, NamedPattern::Twist})
    EXPECT_EQ(trend_of(t, p).kind, TrendKind::Constant) << trend_of(t, p).sentence;
}

TEST(Trends, TwoTeethGiveADifference) {
  const auto flanks =
      fit_teeth({3, 7}, [](int j) { return [j](double, double) { return j == 3 ? 1.0 : 3.0; }; }, 0.5, 11);
  const auto t = fit_tooth_trends(flanks, 20);
  const PatternTrend& o = trend_of(t, NamedPattern::Offset);
  EXPECT_EQ(o.kind, TrendKind::Difference);
  EXPECT_EQ(o.tooth_a, 3);
  EXPECT_EQ(o.tooth_b, 7);
  EXPECT_NEAR(o.difference_um.value, 2.0, 3 * o.difference_um.standard_error);
  EXPECT_NE(o.sentence.find("between tooth 3 and tooth 7"), std::string::npos) << o.sentence;
  EXPECT_EQ(trend_of(t, NamedPattern::Twist).kind, TrendKind::Constant); // both 0
}

TEST(Trends, AlternatingOffsetsAreIrregular) {
  std::vector<int> teeth{1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  const auto flanks =
      fit_teeth(teeth, [](int j) { return [j](double, double) { return j % 2 ? 1.5 : -1.5; }; }, 0.5, 60);
  const auto t = fit_tooth_trends(flanks, 35);
  const PatternTrend& o = trend_of(t, NamedPattern::Offset);
  EXPECT_EQ(o.kind, TrendKind::Irregular) << o.sentence;
  // The scatter (±1.5 µm) is far beyond the fit's standard errors (≈ 0.06 µm each), so the standard error of the
  // mean is scaled up to it: ≈ 1.5/√10 ≈ 0.47 µm, not ≈ 0.02 µm.
  EXPECT_GT(o.mean_um.standard_error, 0.3);
  EXPECT_LT(o.mean_um.standard_error, 0.7);
}

TEST(Trends, RefusesBadInput) {
  auto flanks = fit_teeth({1, 2}, [](int) { return [](double, double) { return 0.0; }; }, 0.5, 1);
  EXPECT_THROW(fit_tooth_trends(std::span(flanks).first(1), 10), std::invalid_argument);
  EXPECT_THROW(fit_tooth_trends(flanks, 1), std::invalid_argument);
  auto dup = flanks;
  dup[1].tooth = 1;
  EXPECT_THROW(fit_tooth_trends(dup, 10), std::invalid_argument);
  auto mixed = flanks;
  mixed[1].side = Flank::Left;
  EXPECT_THROW(fit_tooth_trends(mixed, 10), std::invalid_argument);
  auto outside = flanks;
  outside[1].tooth = 11;
  EXPECT_THROW(fit_tooth_trends(outside, 10), std::invalid_argument);
  auto nan = flanks;
  nan[0].twist_um.value = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(fit_tooth_trends(nan, 10), std::invalid_argument);
}

} // namespace
