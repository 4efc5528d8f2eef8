// geartopo tests — failing regions named in gear terms, on grids and scattered points (docs/residual-patterns.md,
// section 3). Units: ξ, z mm; residuals, σ µm.
#include "diagnosis/residual_fixtures.hpp"

#include "geartopo/diagnosis/residuals/failing_regions.hpp"

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

// ----------------------------------------------------------------------------------------- 3. failing regions


/// 10 µm Gaussian bump of width 0.3 (normalised) centred at the tip side of the datum face edge (u 0.8, w −1).
double tip_datum_bump(double u, double w) {
  return 10.0 * std::exp(-((u - 0.8) * (u - 0.8) + (w + 1.0) * (w + 1.0)) / (2 * 0.3 * 0.3));
}

TEST(Regions, BumpInTheTipHalfNearTheDatumFace) {
  const double sigma = 0.5;
  for (const GridSize g : kGrids) {
    const auto f = grid(g.nxi, g.nz, tip_datum_bump, sigma, 31, 18, Flank::Right);
    const auto regions = find_failing_regions(f, region_options(sigma));
    ASSERT_GE(regions.size(), 1u);
    const FailingRegion& r = regions.front(); // the largest
    EXPECT_EQ(r.sign, +1);
    EXPECT_TRUE(r.profile_zone == ProfileZone::TipThird || r.profile_zone == ProfileZone::TipHalf);
    EXPECT_EQ(r.axial_zone, AxialZone::DatumFaceEnd);
    EXPECT_EQ(r.axial_growth, AxialGrowth::TowardsDatumFace);
    EXPECT_TRUE(contains(r.words, "tip")) << r.words;
    EXPECT_TRUE(contains(r.words, "datum face")) << r.words;
    EXPECT_TRUE(contains(r.sentence, "tooth 18, right flank")) << r.sentence;
    EXPECT_TRUE(contains(r.sentence, "thicker")) << r.sentence;
    EXPECT_EQ(r.extreme_z_mm, kZ0);
    EXPECT_GT(r.extreme_um, 8.0);
    EXPECT_GE(r.xi_min_mm, kXi0 + 0.5 * kLa); // nothing in the root half
    EXPECT_EQ(r.point_indices.size() > 3, true);
    // Every point of the region fails, every failing point of the bump is in it.
    for (std::size_t i : r.point_indices) EXPECT_GT(f.points[i].residual_um, 3 * sigma);
    // Noise elsewhere may add isolated single points, but no other sizeable region.
    for (std::size_t k = 1; k < regions.size(); ++k) EXPECT_LE(regions[k].point_indices.size(), 2u);
  }
}

TEST(Regions, UniformOffsetIsTheWholeFlankThickerOrThinner) {
  const double sigma = 0.5;
  for (const double c : {+6.2, -6.2}) {
    const auto f = grid(7, 9, [c](double, double) { return c; }, sigma, 5, 1, Flank::Left);
    const auto regions = find_failing_regions(f, region_options(sigma));
    ASSERT_EQ(regions.size(), 1u);
    const FailingRegion& r = regions.front();
    EXPECT_EQ(r.point_indices.size(), 63u);
    EXPECT_EQ(r.profile_zone, ProfileZone::Whole);
    EXPECT_EQ(r.axial_zone, AxialZone::Whole);
    EXPECT_EQ(r.profile_growth, ProfileGrowth::None);
    EXPECT_EQ(r.axial_growth, AxialGrowth::None);
    EXPECT_FALSE(r.peaked);
    EXPECT_NEAR(r.mean_um, c, 3 * sigma / std::sqrt(63.0));
    EXPECT_TRUE(contains(r.sentence, "tooth 1, left flank, whole flank")) << r.sentence;
    EXPECT_TRUE(contains(r.sentence, "uniform")) << r.sentence;
    EXPECT_TRUE(contains(r.sentence, c > 0 ? "thicker" : "thinner")) << r.sentence;
    EXPECT_FALSE(contains(r.sentence, c > 0 ? "thinner" : "thicker")) << r.sentence;
  }
}

TEST(Regions, SteepProfileSlopeFailsAtBothEndsGrowingOutwards) {
  // 8 µm · u: plus material at the tip, minus at the root, both growing away from the middle.
  const auto f = grid(7, 9, [](double u, double) { return 8.0 * u; });
  const auto regions = find_failing_regions(f, region_options(0.5));
  ASSERT_EQ(regions.size(), 2u);
  for (const FailingRegion& r : regions) {
    EXPECT_EQ(r.axial_zone, AxialZone::Whole);
    EXPECT_EQ(r.point_indices.size(), 27u); // rows u = ±1/3, ±2/3, ±1 of 9 columns
    if (r.sign > 0) {
      EXPECT_EQ(r.profile_zone, ProfileZone::TipThird);
      EXPECT_EQ(r.profile_growth, ProfileGrowth::TowardsTip);
      EXPECT_TRUE(contains(r.words, "growing towards the tip")) << r.words;
    } else {
      EXPECT_EQ(r.profile_zone, ProfileZone::RootThird);
      EXPECT_EQ(r.profile_growth, ProfileGrowth::TowardsRoot);
      EXPECT_TRUE(contains(r.sentence, "thinner")) << r.sentence;
    }
  }
}

TEST(Regions, BumpAndHollowAreSeparateRegions) {
  const auto f = grid(20, 40, [](double u, double w) {
    return 6.0 * std::exp(-((u + 0.6) * (u + 0.6) + (w - 0.6) * (w - 0.6)) / 0.02) -
           5.0 * std::exp(-((u - 0.5) * (u - 0.5) + (w + 0.2) * (w + 0.2)) / 0.02);
  });
  const auto regions = find_failing_regions(f, region_options(0.5));
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_EQ(regions[0].sign, +1);
  EXPECT_EQ(regions[0].profile_zone, ProfileZone::RootThird);
  EXPECT_EQ(regions[0].axial_zone, AxialZone::FarFaceEnd);
  EXPECT_TRUE(regions[0].peaked);
  EXPECT_TRUE(contains(regions[0].words, "local bump")) << regions[0].words;
  EXPECT_EQ(regions[1].sign, -1);
  EXPECT_TRUE(regions[1].profile_zone == ProfileZone::TipThird || regions[1].profile_zone == ProfileZone::TipHalf);
  EXPECT_EQ(regions[1].axial_zone, AxialZone::Middle);
  EXPECT_TRUE(contains(regions[1].words, "local hollow")) << regions[1].words;
}

TEST(Regions, OnAGridOnlyNeighbouringCellsConnect) {
  // Two bands of +5 µm across the whole profile at w ∈ {−0.5, −0.25} and {0.25, 0.5}, with the passing column w = 0
  // between them: two regions on the 7 × 9 grid (8-neighbours), 14 points each.
  const auto f = grid(7, 9, [](double, double w) {
    return std::abs(std::abs(w) - 0.375) < 0.2 ? 5.0 : 0.0;
  });
  const auto regions = find_failing_regions(f, region_options(0.5));
  ASSERT_EQ(regions.size(), 2u);
  for (const auto& r : regions) {
    EXPECT_EQ(r.point_indices.size(), 14u);
    EXPECT_EQ(r.profile_zone, ProfileZone::Whole);
  }
  const bool first_is_datum = regions[0].z_max_mm < 75.0;
  EXPECT_EQ(regions[first_is_datum ? 0 : 1].axial_zone, AxialZone::DatumFaceHalf);
  EXPECT_EQ(regions[first_is_datum ? 1 : 0].axial_zone, AxialZone::FarFaceHalf);
  EXPECT_TRUE(contains(regions[first_is_datum ? 0 : 1].words, "whole profile, half towards the datum face"))
      << regions[first_is_datum ? 0 : 1].words;
}

TEST(Regions, ScatteredPointsAreGroupedByProximity) {
  // Points scattered uniformly over the flank (no grid), a noise-free bump in the root third near the far face. 300
  // points, and 20 000 — a point cloud's density, where an all-pairs neighbour search or a wavelength scan growing
  // with the point count took 40 s per flank (the ctest timeout catches that; the answer must not change).
  for (int n : {300, 20000}) {
    SCOPED_TRACE(n);
    Gauss g(99);
    FlankResiduals f{2, Flank::Left, {}, kXi0, kXi1, kZ0, kZ1};
    for (int i = 0; i < n; ++i) {
      const double xi = kXi0 + kLa * g.uniform(), z = kZ0 + kLb * g.uniform();
      const double u = u_of(xi), w = w_of(z);
      f.points.push_back({xi, z, -9.0 * std::exp(-((u + 0.75) * (u + 0.75) + (w - 0.75) * (w - 0.75)) / 0.08)});
    }
    const auto regions = find_failing_regions(f, region_options(0.5));
    std::size_t failing = 0;
    for (const auto& p : f.points) failing += std::abs(p.residual_um) > 1.5;
    if (n == 300) {
      ASSERT_EQ(regions.size(), 1u);
      EXPECT_EQ(regions[0].point_indices.size(), failing);
    } else {
      // KNOWN LIMITATION (closing note 2026-11-21): at point-cloud density the 3 × median-spacing link leaves a few
      // dozen small fragments beside the main region (the former all-pairs search gave the same 24 regions).
      ASSERT_FALSE(regions.empty());
      std::size_t largest = 0;
      for (const auto& r : regions) largest = std::max(largest, r.point_indices.size());
      EXPECT_GT(largest, failing / 2) << "the bump's main region";
    }
    for (const auto& r : regions) {
      EXPECT_EQ(r.sign, -1);
      EXPECT_TRUE(contains(r.words, "root")) << r.words;
      EXPECT_TRUE(contains(r.words, "far face")) << r.words;
      EXPECT_TRUE(contains(r.sentence, "thinner")) << r.sentence;
    }
    // The patterns of the same flank: the scan stops at L/64, whatever the point count.
    const auto pat = fit_flank_patterns(f, with_noise(0.5));
    EXPECT_GE(pat.waviness_profile.min_wavelength_mm, kLa / 64.0 - 1e-9);
    EXPECT_GE(pat.waviness_helix.min_wavelength_mm, kLb / 64.0 - 1e-9);
  }
}

TEST(Regions, NothingIsMarkedOnPureNoiseOnTheCoarseGrid) {
  // Seed 2 was checked to give no |residual| > 3σ among the 63 points (expected 0.17 such points per flank).
  const double sigma = 1.0;
  const auto f = grid(7, 9, [](double, double) { return 0.0; }, sigma, 2);
  EXPECT_TRUE(find_failing_regions(f, region_options(sigma)).empty());
}

TEST(Regions, FalseAlarmCountOnPureNoiseIsSmall) {
  // 20 dense flanks of pure noise: expected 0.27 % of 16000 points = 43 marked points (sd ≈ 6.6); allow 70.
  const double sigma = 1.0;
  std::size_t marked = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed)
    for (const auto& r : find_failing_regions(grid(20, 40, [](double, double) { return 0.0; }, sigma, seed),
                                              region_options(sigma)))
      marked += r.point_indices.size();
  EXPECT_LE(marked, 70u);
}

} // namespace
