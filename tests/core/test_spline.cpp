// geartopo tests — cubic spline interpolation of error tables: exact on cubics, C² across the C seam.
// Units: arbitrary (the spline is unit-free).
#include "geartopo/core/cubic_spline.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

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

/// The documented interval of t (x_i ≤ t < x_{i+1}, the last one for t = x_{n−1}) by bisection over the knots alone:
/// the largest i ≤ n − 2 with x_i ≤ t, 0 if none.
std::size_t bisected_interval(const std::vector<double>& x, double t) {
  const auto k = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), t) - x.begin());
  return k == 0 ? 0 : std::min(k - 1, x.size() - 2);
}

/// Points where a lookup can go wrong: every knot, its neighbours one ulp either side, the midpoints, and random
/// points over the table.
std::vector<double> probe_points(const std::vector<double>& x, std::mt19937& rng) {
  std::vector<double> t;
  for (std::size_t i = 0; i < x.size(); ++i) {
    t.push_back(x[i]);
    t.push_back(std::nextafter(x[i], -1e300));
    t.push_back(std::nextafter(x[i], 1e300));
    if (i + 1 < x.size()) t.push_back(0.5 * (x[i] + x[i + 1]));
  }
  std::uniform_real_distribution<double> u(x.front(), x.back());
  for (int k = 0; k < 2000; ++k) t.push_back(u(rng));
  return t;
}

TEST(CubicSpline, LocatesTheIntervalBisectionFindsOnEvenAndUnevenKnots) {
  // Even knots as the shipped tables have them (exact multiples of 50 mm; 5° steps in rad, which are not exactly even
  // in binary; steps of 0.1, not representable) and uneven ones. Truth: bisection over the knots (bisected_interval).
  std::vector<double> mm, deg5, tenth, uneven = {-3.0, -2.1, -0.4, 0.0, 1.7, 2.2, 4.9, 5.0, 8.3};
  for (int i = 0; i <= 18; ++i) mm.push_back(50.0 * i);
  for (int i = 0; i <= 72; ++i) deg5.push_back(5.0 * i * std::numbers::pi / 180.0);
  for (int i = 0; i <= 40; ++i) tenth.push_back(-2.0 + 0.1 * i);
  // Many uneven knots as the wheel profile has them (~2 000): a dense cluster (60 knots in 0.3), sparse ends and
  // spacings growing along the span, so some of the located buckets hold many knots and many hold none.
  std::vector<double> clustered{0.0};
  for (int i = 1; i < 400; ++i) clustered.push_back(clustered.back() + (i > 200 && i <= 260 ? 0.005 : 0.01 + 1e-4 * i));
  std::mt19937 rng(7);
  for (const auto* x : {&mm, &deg5, &tenth, &uneven, &clustered}) {
    std::vector<double> y;
    for (double v : *x) y.push_back(std::sin(v));
    const CubicSpline s(*x, y, CubicSpline::Ends::NotAKnot);
    EXPECT_EQ(s.evenly_spaced(), x != &uneven && x != &clustered);
    for (double t : probe_points(*x, rng)) {
      if (t < x->front() || t > x->back()) continue; // outside: the tangent lines (ContinuesAsTheEndTangent…)
      const CubicSpline::Location l = s.locate(t);
      ASSERT_FALSE(l.below || l.above);
      ASSERT_EQ(l.i, bisected_interval(*x, t)) << "t = " << t << " on " << x->size() << " knots";
      // The local coordinates of the moment form, from their definition.
      const double h = (*x)[l.i + 1] - (*x)[l.i];
      EXPECT_EQ(l.a, ((*x)[l.i + 1] - t) / h);
      EXPECT_EQ(l.b, (t - (*x)[l.i]) / h);
    }
  }
}

TEST(CubicSpline, PeriodicLookupWrapsOntoTheBisectedInterval) {
  std::vector<double> x, y;
  for (int i = 0; i <= 36; ++i) {
    x.push_back(10.0 * i * std::numbers::pi / 180.0);
    y.push_back(i == 36 ? 0.0 : std::sin(3.0 * x.back()) + 0.1 * (i % 5));
  }
  y.back() = y.front();
  const CubicSpline s(x, y, CubicSpline::Ends::Periodic);
  ASSERT_TRUE(s.evenly_spaced());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0 * kTwoPi, 3.0 * kTwoPi);
  for (int k = 0; k < 2000; ++k) {
    const double t = u(rng);
    const CubicSpline::Location l = s.locate(t);
    ASSERT_GE(l.t, x.front());
    ASSERT_LT(l.t, x.back());
    EXPECT_NEAR(std::remainder(l.t - t, kTwoPi), 0.0, 1e-14); // the same angle, one turn apart
    ASSERT_EQ(l.i, bisected_interval(x, l.t));
  }
}

TEST(CubicSpline, OneLookupServesEverySplineWithTheSameKnots) {
  // value_at(another spline's locate(t)) is value(t) bit for bit when the knots are the same (the six error components
  // of one axis table): the lookup depends on the knots only.
  std::vector<double> x, y1, y2;
  for (int i = 0; i <= 20; ++i) {
    x.push_back(25.0 * i);
    y1.push_back(std::cos(0.01 * x.back()));
    y2.push_back(1e-3 * x.back() * x.back());
  }
  const CubicSpline a(x, y1, CubicSpline::Ends::NotAKnot), b(x, y2, CubicSpline::Ends::NotAKnot);
  std::mt19937 rng(3);
  auto points = probe_points(x, rng);
  points.insert(points.end(), {-40.0, -1e-9, 500.0 + 1e-9, 612.5}); // outside on both sides: the end tangents
  for (double t : points) {
    EXPECT_EQ(b.value_at(a.locate(t)), b.value(t)) << t;
    EXPECT_EQ(a.value_at(a.locate(t)), a.value(t)) << t;
  }
}

} // namespace
} // namespace geartopo::machine

// second_derivative_bound: |s″| within `reach` of t never exceeds it. The truth is the second difference of value()
// (step 1e-3 on knots ≥ 0.05 apart: exact for a cubic piece, so within rounding ~1e-9 unless τ ± 1e-3 crosses a knot,
// where it averages the two pieces' s″, still below the bound), at 41 points within reach of t, on uneven knots,
// for reaches below the smallest spacing (the local bound) and above it (the global one).
TEST(CubicSpline, SecondDerivativeBoundHoldsWithinItsReach) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> gap(0.05, 0.4), value(-1.0, 1.0);
  std::vector<double> x{0.0}, y{value(rng)};
  for (int i = 1; i < 60; ++i) x.push_back(x.back() + gap(rng)), y.push_back(std::sin(3.0 * x.back()) + 0.1 * value(rng));
  const geartopo::CubicSpline s(x, y, geartopo::CubicSpline::Ends::NotAKnot);
  const double e = 1e-3;
  int local_smaller = 0;
  std::uniform_real_distribution<double> where(x.front() - 0.2, x.back() + 0.2);
  for (int k = 0; k < 2000; ++k) {
    const double t = where(rng);
    const auto l = s.locate(t);
    for (double reach : {1e-6, 0.01, 0.04, 1.0}) {
      const double bound = s.second_derivative_bound(l, reach);
      if (reach < 0.05 && bound < s.second_derivative_bound(l, 1.0)) ++local_smaller;
      for (int j = -20; j <= 20; ++j) {
        const double tau = t + reach * j / 20.0;
        const double d2 = (s.value(tau + e) - 2.0 * s.value(tau) + s.value(tau - e)) / (e * e);
        ASSERT_LE(std::abs(d2), bound + 1e-6) << "t " << t << " reach " << reach << " tau " << tau;
      }
    }
  }
  EXPECT_GT(local_smaller, 1000) << "near a point the bound should be the local one, not the whole spline's";
}
