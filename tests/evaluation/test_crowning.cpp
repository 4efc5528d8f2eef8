// Crowning C of a trace: known answers from the definition (height of the fitted parabola at mid range above its
// chord over the range, docs/iso1328.md "Crowning").
#include "geartopo/evaluation/crowning.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>

namespace {

using geartopo::evaluation::Trace;

/// n points over [s0, s1] of f(s), evaluation range [a, b].
Trace sampled_trace(const std::function<double(double)>& f, double s0, double s1, double a, double b, int n = 41) {
  Trace t;
  for (int i = 0; i < n; ++i) {
    const double s = s0 + (s1 - s0) * i / (n - 1);
    t.position_mm.push_back(s);
    t.deviation_um.push_back(f(s));
  }
  t.range_start_mm = a;
  t.range_end_mm = b;
  return t;
}

} // namespace

TEST(Crowning, ParabolaOfKnownHeightAboveItsChord) {
  // d(s) = 3 − 4 (s − 20)²/10² µm over L = 20 mm centred on 20: 3 µm at the middle, −1 µm at both ends → C = 4 µm.
  const auto t = sampled_trace([](double s) { return 3.0 - 4.0 * (s - 20.0) * (s - 20.0) / 100.0; }, 8.0, 32.0, 10.0, 30.0);
  EXPECT_NEAR(geartopo::evaluation::crowning_um(t), 4.0, 1e-9);
}

TEST(Crowning, OffsetAndSlopeDoNotChangeIt) {
  const auto bowl = [](double s) { return 0.5 * (s - 5.0) * (s - 5.0) / 25.0; }; // hollow: chord 0.5 above the middle
  const auto tilted = [&](double s) { return bowl(s) + 7.0 - 0.3 * s; };
  const double c0 = geartopo::evaluation::crowning_um(sampled_trace(bowl, 0.0, 10.0, 0.0, 10.0));
  const double c1 = geartopo::evaluation::crowning_um(sampled_trace(tilted, 0.0, 10.0, 0.0, 10.0));
  EXPECT_NEAR(c0, -0.5, 1e-9);
  EXPECT_NEAR(c1, c0, 1e-9);
}

TEST(Crowning, OnlyTheEvaluationRangeCounts) {
  // Straight inside [10, 30], a steep bend outside it: no crowning.
  const auto f = [](double s) { return s < 10.0 ? 5.0 * (10.0 - s) * (10.0 - s) : 0.2 * s; };
  EXPECT_NEAR(geartopo::evaluation::crowning_um(sampled_trace(f, 0.0, 30.0, 10.0, 30.0, 61)), 0.0, 1e-9);
}

TEST(Crowning, RejectsATraceThatDoesNotCoverTheRange) {
  const auto t = sampled_trace([](double) { return 0.0; }, 0.0, 5.0, 0.0, 10.0);
  EXPECT_THROW(geartopo::evaluation::crowning_um(t), std::invalid_argument);
}
