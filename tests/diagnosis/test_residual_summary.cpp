// geartopo tests — summary statistics of residuals, and the refusal of invalid input by every part of the residual
// analysis (docs/residual-patterns.md, section 4 and "Input"). Units: ξ, z mm; residuals, σ µm.
#include "diagnosis/residual_fixtures.hpp"

#include "geartopo/diagnosis/residuals/failing_regions.hpp"
#include "geartopo/diagnosis/residuals/flank_patterns.hpp"
#include "geartopo/diagnosis/residuals/residual_summary.hpp"

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

// ----------------------------------------------------------------------------------------- 4. statistics

TEST(Summary, RmsAndMaximumPerFlankToothSideAndOverall) {
  std::vector<FlankResiduals> flanks{
      grid(7, 9, [](double, double) { return 2.0; }, 0.0, 1, 1, Flank::Left),
      grid(7, 9, [](double, double) { return -3.0; }, 0.0, 1, 1, Flank::Right),
      grid(7, 9, [](double, double) { return 1.0; }, 0.0, 1, 2, Flank::Right),
  };
  flanks[1].points[10].residual_um = -7.0;
  flanks[2].points.push_back({kXi1 + 1.0, 50.0, 99.0}); // outside L_α: ignored, counted
  const auto s = summarize_residuals(flanks);
  ASSERT_EQ(s.flanks.size(), 3u);
  EXPECT_EQ(s.flanks[0].tooth, 1);
  EXPECT_EQ(s.flanks[0].side, Flank::Left);
  EXPECT_NEAR(s.flanks[0].stats.rms_um, 2.0, 1e-12);
  EXPECT_NEAR(s.flanks[1].stats.max_abs_um, 7.0, 1e-12);
  EXPECT_NEAR(s.flanks[1].stats.extreme_um, -7.0, 1e-12);
  EXPECT_NEAR(s.flanks[1].stats.rms_um, std::sqrt((62 * 9.0 + 49.0) / 63), 1e-12);
  EXPECT_EQ(s.flanks[2].points_outside_range, 1u);
  EXPECT_NEAR(s.flanks[2].stats.max_abs_um, 1.0, 1e-12);
  ASSERT_EQ(s.teeth.size(), 2u);
  EXPECT_NEAR(s.teeth[0].stats.rms_um, std::sqrt((63 * 4.0 + 62 * 9.0 + 49.0) / 126), 1e-12);
  EXPECT_EQ(s.teeth[0].stats.points, 126u);
  ASSERT_EQ(s.sides.size(), 2u);
  EXPECT_EQ(s.sides[1].side, Flank::Right);
  EXPECT_EQ(s.sides[1].flanks, 2u);
  EXPECT_NEAR(s.sides[1].stats.rms_um, std::sqrt((62 * 9.0 + 49.0 + 63 * 1.0) / 126), 1e-12);
  EXPECT_EQ(s.overall.points, 189u);
  EXPECT_NEAR(s.overall.extreme_um, -7.0, 1e-12);
  EXPECT_EQ(s.overall.extreme_tooth, 1);
  EXPECT_EQ(s.overall.extreme_side, Flank::Right);
  EXPECT_NEAR(s.overall.extreme_xi_mm, flanks[1].points[10].xi_mm, 1e-12);
}

// ----------------------------------------------------------------------------------------- invalid input

TEST(ResidualPatterns, RefusesInvalidInput) {
  const auto good = grid(7, 9, [](double, double) { return 0.0; });
  const auto opt = with_noise(0.5);
  EXPECT_NO_THROW(fit_flank_patterns(good, opt));

  auto nan = good;
  nan.points[5].residual_um = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(fit_flank_patterns(nan, opt), std::invalid_argument);
  EXPECT_THROW(find_failing_regions(nan, region_options(0.5)), std::invalid_argument);
  EXPECT_THROW(summarize_residuals(std::vector<FlankResiduals>{nan}), std::invalid_argument);

  auto empty = good;
  empty.points.clear();
  EXPECT_THROW(fit_flank_patterns(empty, opt), std::invalid_argument);
  EXPECT_THROW(find_failing_regions(empty, region_options(0.5)), std::invalid_argument);

  auto zero_range = good;
  zero_range.z_end_mm = zero_range.z_start_mm;
  EXPECT_THROW(fit_flank_patterns(zero_range, opt), std::invalid_argument);
  auto inf_range = good;
  inf_range.xi_end_mm = std::numeric_limits<double>::infinity();
  EXPECT_THROW(fit_flank_patterns(inf_range, opt), std::invalid_argument);

  auto few = good;
  few.points.resize(5);
  EXPECT_THROW(fit_flank_patterns(few, opt), std::invalid_argument);
  auto two_rows = grid(2, 9, [](double, double) { return 0.0; });
  EXPECT_THROW(fit_flank_patterns(two_rows, opt), std::invalid_argument);
  auto outside = good;
  for (auto& p : outside.points) p.z_mm += 500.0;
  EXPECT_THROW(fit_flank_patterns(outside, opt), std::invalid_argument);
  auto tooth0 = good;
  tooth0.tooth = 0;
  EXPECT_THROW(fit_flank_patterns(tooth0, opt), std::invalid_argument);

  EXPECT_THROW(fit_flank_patterns(good, with_noise(0.0)), std::invalid_argument);
  EXPECT_THROW(fit_flank_patterns(good, with_noise(std::numeric_limits<double>::quiet_NaN())), std::invalid_argument);
  EXPECT_THROW(find_failing_regions(good, region_options(0.5, 0.0)), std::invalid_argument);
  EXPECT_THROW(find_failing_regions(good, region_options(-1.0)), std::invalid_argument);

  EXPECT_THROW(summarize_residuals(std::vector<FlankResiduals>{}), std::invalid_argument);
  EXPECT_THROW(summarize_residuals(std::vector<FlankResiduals>{good, good}), std::invalid_argument);

  try {
    fit_flank_patterns(few, opt);
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(contains(e.what(), "fewer than the 6 pattern parameters")) << e.what();
  }
}

} // namespace
