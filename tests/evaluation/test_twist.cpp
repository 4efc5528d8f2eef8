// Flank twist (evaluation/twist.hpp) against fields whose twist is known in closed form: a bilinear field
// a (ξ − ξ₀)(z − z₀) has the profile slope a (z − z₀) L_α at column z, so S_α = a L_α L_β, and likewise S_β = a L_β L_α;
// a crowning (ξ − ξ₀)² + (z − z₀)² and a plain slope have none.
#include "geartopo/evaluation/twist.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>

using geartopo::evaluation::flank_twist;
using geartopo::evaluation::TwistGridPoint;

namespace {

constexpr double kXi0 = 30.0, kLalpha = 40.0, kZ0 = 7.0, kLbeta = 136.0;

std::vector<TwistGridPoint> grid_of(const std::function<double(double, double)>& f, int rows = 7, int cols = 9) {
  std::vector<TwistGridPoint> g;
  for (int r = 1; r <= rows; ++r)
    for (int c = 1; c <= cols; ++c) {
      const double xi = kXi0 + kLalpha * (r - 1) / (rows - 1), z = kZ0 + kLbeta * (c - 1) / (cols - 1);
      g.push_back({r, c, xi, z, f(xi, z)});
    }
  return g;
}

} // namespace

TEST(FlankTwist, ABilinearFieldTwistsByItsCoefficientTimesBothRanges) {
  const double a = 1e-3; // µm per mm²
  const auto t = flank_twist(grid_of([&](double xi, double z) { return a * (xi - 12.0) * (z - 60.0); }));
  EXPECT_NEAR(t.profile_twist_um, a * kLalpha * kLbeta, 1e-12);
  EXPECT_NEAR(t.helix_twist_um, a * kLbeta * kLalpha, 1e-12);
}

TEST(FlankTwist, CrowningAndSlopesAreNotTwist) {
  const auto t = flank_twist(grid_of([](double xi, double z) {
    return -0.01 * (xi - 50.0) * (xi - 50.0) - 0.002 * (z - 75.0) * (z - 75.0) + 0.1 * xi - 0.03 * z;
  }));
  EXPECT_NEAR(t.profile_twist_um, 0.0, 1e-12);
  EXPECT_NEAR(t.helix_twist_um, 0.0, 1e-12);
  EXPECT_THROW(flank_twist(grid_of([](double, double) { return 0.0; }, 1, 9)), std::invalid_argument);
}
