// covering_scale: the axis range of a deviation chart. Truth: ranges worked out by hand from the rule (smallest
// 1-2-5 step giving at least `target` intervals, ends at whole steps around the values), and properties every range
// must have (contains the values, whole steps, 1-2-5 step).
#include "geartopo/render/scale.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

/// Whether s is 1, 2 or 5 × 10^k.
bool is_one_two_five(double s) {
  const double m = s / std::pow(10.0, std::floor(std::log10(s) + 1e-12));
  return std::abs(m - 1.0) < 1e-9 || std::abs(m - 2.0) < 1e-9 || std::abs(m - 5.0) < 1e-9;
}

} // namespace

TEST(CoveringScale, SubMicrometreTraceGetsAFineScale) {
  // Values −0.3 … 0.7 µm, 6 intervals wanted: 1.0/6 = 0.167 → step 0.2; ends floor(−1.5) = −2 → −0.4, ceil(3.5) = 4 → 0.8.
  const auto s = geartopo::render::covering_scale({-0.3, 0.7, 0.1}, 0.0, 6);
  EXPECT_NEAR(s.step, 0.2, 1e-12);
  EXPECT_NEAR(s.range.min, -0.4, 1e-12);
  EXPECT_NEAR(s.range.max, 0.8, 1e-12);
}

TEST(CoveringScale, MinimumSpanFromTheToleranceWidensAroundTheMiddle) {
  // Values 0.1 … 0.2, at least 10 wide: [−4.85, 5.15]; 10/5 = 2 → step 2; ends −6 and 6.
  const auto s = geartopo::render::covering_scale({0.1, 0.2}, 10.0, 5);
  EXPECT_NEAR(s.step, 2.0, 1e-12);
  EXPECT_NEAR(s.range.min, -6.0, 1e-12);
  EXPECT_NEAR(s.range.max, 6.0, 1e-12);
}

TEST(CoveringScale, AlwaysContainsTheValuesInWholeOneTwoFiveSteps) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> centre(-50.0, 50.0), log_span(-2.0, 2.0), unit(0.0, 1.0);
  for (int trial = 0; trial < 500; ++trial) {
    const double c = centre(rng), span = std::pow(10.0, log_span(rng));
    std::vector<double> v;
    for (int i = 0; i < 20; ++i) v.push_back(c + span * (unit(rng) - 0.5));
    const double min_span = trial % 2 ? 0.0 : 3.0 * span * unit(rng);
    const auto s = geartopo::render::covering_scale(v.data(), v.size(), min_span, 6);
    for (double x : v) {
      EXPECT_LE(s.range.min, x);
      EXPECT_GE(s.range.max, x);
    }
    EXPECT_GE(s.range.max - s.range.min, min_span * (1.0 - 1e-12));
    EXPECT_TRUE(is_one_two_five(s.step)) << s.step;
    const double steps = (s.range.max - s.range.min) / s.step;
    EXPECT_NEAR(steps, std::round(steps), 1e-6);
    EXPECT_LE(steps, 12.0 + 1e-9);
    EXPECT_NEAR(s.range.min / s.step, std::round(s.range.min / s.step), 1e-6);
  }
}

TEST(CoveringScale, IgnoresNonFiniteValuesAndRejectsBadArguments) {
  const auto s = geartopo::render::covering_scale({NAN, 1.0, 2.0, INFINITY}, 0.0, 6);
  EXPECT_LE(s.range.min, 1.0);
  EXPECT_GE(s.range.max, 2.0);
  EXPECT_LT(s.range.max - s.range.min, 3.0);
  EXPECT_THROW(geartopo::render::covering_scale({1.0}, -1.0, 6), std::invalid_argument);
  EXPECT_THROW(geartopo::render::covering_scale({1.0}, 0.0, 1), std::invalid_argument);
}

TEST(CoveringScale, TickLabelsHaveTheDecimalsOfTheStepAndNoNegativeZero) {
  EXPECT_EQ(geartopo::render::tick_label(-0.4, 0.2), "-0.4");
  EXPECT_EQ(geartopo::render::tick_label(-0.0, 0.2), "0.0");
  EXPECT_EQ(geartopo::render::tick_label(10.0, 5.0), "10");
  EXPECT_EQ(geartopo::render::tick_label(0.05, 0.05), "0.05");
}
