// geartopo tests — cubic spline interpolation of error tables: exact on cubics, C² across the C seam.
// Units: arbitrary (the spline is unit-free).
#include "geartopo/core/cubic_spline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace geartopo::machine {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

double cubic(double x) { return 0.7 - 1.3 * x + 0.25 * x * x + 0.031 * x * x * x; }
double cubic_d(double x) { return -1.3 + 0.5 * x + 0.093 * x * x; }
double cubic_dd(double x) { return 0.5 + 0.186 * x; }

TEST(CubicSpline, NotAKnotReproducesACubicExactlyOnUnevenKnots) {
  const std::vector<double> x = {-3.0, -2.1, -0.4, 0.0, 1.7, 2.2, 4.9, 5.0, 8.3};
  std::vector<double> y;
  for (double v : x) y.push_back(cubic(v));
  const CubicSpline s(x, y, CubicSpline::Ends::NotAKnot);
  for (double t = -3.0; t <= 8.3; t += 0.037) {
    EXPECT_NEAR(s.value(t), cubic(t), 1e-12 * (1.0 + std::abs(cubic(t))));
    EXPECT_NEAR(s.derivative(t), cubic_d(t), 1e-11);
    EXPECT_NEAR(s.second_derivative(t), cubic_dd(t), 1e-10);
  }
}

TEST(CubicSpline, FourKnotsIsTheInterpolatingCubic) {
  const std::vector<double> x = {0.0, 1.0, 3.0, 4.5};
  std::vector<double> y;
  for (double v : x) y.push_back(cubic(v));
  const CubicSpline s(x, y, CubicSpline::Ends::NotAKnot);
  for (double t = 0.0; t <= 4.5; t += 0.1) EXPECT_NEAR(s.value(t), cubic(t), 1e-12);
}

TEST(CubicSpline, ThreeKnotsIsTheParabolaTwoKnotsTheLine) {
  const auto parabola = [](double x) { return 2.0 - x + 0.5 * x * x; };
  const CubicSpline p({0.0, 1.0, 3.0}, {parabola(0.0), parabola(1.0), parabola(3.0)}, CubicSpline::Ends::NotAKnot);
  for (double t = 0.0; t <= 3.0; t += 0.1) EXPECT_NEAR(p.value(t), parabola(t), 1e-13);
  const CubicSpline l({1.0, 3.0}, {5.0, 9.0}, CubicSpline::Ends::NotAKnot);
  EXPECT_NEAR(l.value(2.5), 8.0, 1e-14);
  EXPECT_NEAR(l.derivative(1.2), 2.0, 1e-14);
}

TEST(CubicSpline, ContinuesAsTheEndTangentOutsideTheTable) {
  const std::vector<double> x = {0.0, 1.0, 2.0, 3.0, 4.0};
  std::vector<double> y;
  for (double v : x) y.push_back(cubic(v));
  const CubicSpline s(x, y, CubicSpline::Ends::NotAKnot);
  EXPECT_NEAR(s.value(5.0), cubic(4.0) + cubic_d(4.0) * 1.0, 1e-12);
  EXPECT_NEAR(s.value(-0.5), cubic(0.0) - cubic_d(0.0) * 0.5, 1e-12);
}

double periodic_f(double t) { return std::sin(t) + 0.3 * std::cos(2.0 * t) - 0.1 * std::sin(3.0 * t); }

TEST(CubicSpline, PeriodicTableIsC2AcrossTheSeam) {
  std::vector<double> x, y;
  for (int k = 0; k <= 24; ++k) { // every 15°, [0, 360] closed
    x.push_back(kTwoPi * k / 24.0);
    y.push_back(periodic_f(x.back()));
  }
  y.back() = y.front();
  const CubicSpline s(x, y, CubicSpline::Ends::Periodic);
  const double eps = 1e-9;
  const double before = kTwoPi - eps, after = eps;
  EXPECT_NEAR(s.value(before), s.value(after), 1e-8);
  EXPECT_NEAR(s.derivative(before), s.derivative(after), 1e-8);
  EXPECT_NEAR(s.second_derivative(before), s.second_derivative(after), 1e-7);
  // Wrapping: one turn later or earlier is the same point.
  for (double t = 0.05; t < kTwoPi; t += 0.31) {
    EXPECT_NEAR(s.value(t + kTwoPi), s.value(t), 1e-12);
    EXPECT_NEAR(s.value(t - 2.0 * kTwoPi), s.value(t), 1e-12);
  }
  // Interpolation error of a cubic spline at 15° spacing: (5/384)·h⁴·max|f⁗| ≈ 4e-4.
  for (double t = 0.0; t < kTwoPi; t += 0.01) EXPECT_NEAR(s.value(t), periodic_f(t), 1e-3);

  // The same data with ordinary (not-a-knot) ends is visibly not C² at the seam: the check above can fail.
  const CubicSpline open(x, y, CubicSpline::Ends::NotAKnot);
  EXPECT_GT(std::abs(open.second_derivative(x.back()) - open.second_derivative(x.front())), 1e-3);
}

TEST(CubicSpline, PeriodicWithFewKnots) {
  // Two and three intervals use the dense solve; a constant table stays constant.
  const CubicSpline two({0.0, std::numbers::pi, kTwoPi}, {1.0, -1.0, 1.0}, CubicSpline::Ends::Periodic);
  EXPECT_NEAR(two.derivative(1e-12), two.derivative(kTwoPi - 1e-12), 1e-9);
  EXPECT_NEAR(two.value(std::numbers::pi), -1.0, 1e-14);
  const CubicSpline flat({0.0, kTwoPi}, {2.0, 2.0}, CubicSpline::Ends::Periodic);
  EXPECT_EQ(flat.value(1.0), 2.0);
}

TEST(CubicSpline, RejectsBadKnots) {
  EXPECT_THROW(CubicSpline({0.0}, {1.0}, CubicSpline::Ends::NotAKnot), std::invalid_argument);
  EXPECT_THROW(CubicSpline({0.0, 0.0, 1.0}, {1.0, 2.0, 3.0}, CubicSpline::Ends::NotAKnot), std::invalid_argument);
  EXPECT_THROW(CubicSpline({0.0, 1.0, 2.0}, {1.0, 2.0, 3.0}, CubicSpline::Ends::Periodic), std::invalid_argument);
}

} // namespace
} // namespace geartopo::machine
