// Brent's minimisation against minima known in closed form.
#include "geartopo/core/minimize.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace geartopo {
namespace {

TEST(MinimizeBrent, FindsTheVertexOfAParabolaToTheTolerance) {
  const Minimum m = minimize_brent([](double x) { return 2.5 * (x - 1.234) * (x - 1.234) + 3.0; }, 0.0, 5.0, 1e-9);
  EXPECT_NEAR(m.x, 1.234, 1e-8);
  EXPECT_NEAR(m.value, 3.0, 1e-15);
}

TEST(MinimizeBrent, FindsPiAsTheMinimumOfTheCosine) {
  int calls = 0;
  const Minimum m = minimize_brent([&](double x) { ++calls; return std::cos(x); }, 2.0, 4.0, 1e-8);
  EXPECT_NEAR(m.x, std::numbers::pi, 1e-7);
  EXPECT_NEAR(m.value, -1.0, 1e-14);
  EXPECT_LT(calls, 30); // parabolic steps, not golden sections only (those would need ~40 for 2/1e-8)
}

TEST(MinimizeBrent, AMonotonicFunctionEndsAtTheBracketEdge) {
  const Minimum m = minimize_brent([](double x) { return x; }, -1.0, 1.0, 1e-7);
  EXPECT_NEAR(m.x, -1.0, 1e-6);
}

TEST(MinimizeBrent, RefusesAnEmptyBracketOrNoTolerance) {
  EXPECT_THROW(minimize_brent([](double x) { return x; }, 1.0, 1.0, 1e-7), std::invalid_argument);
  EXPECT_THROW(minimize_brent([](double x) { return x; }, 0.0, 1.0, 0.0), std::invalid_argument);
}

} // namespace
} // namespace geartopo
