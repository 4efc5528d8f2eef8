// geartopo tests — named patterns and waviness of one flank's residual on synthetic fields with known answers
// (docs/residual-patterns.md, section 1). Units: ξ, z, wavelengths mm; residuals, patterns, σ µm; angles rad.
#include "diagnosis/residual_fixtures.hpp"

#include "geartopo/diagnosis/residuals/flank_patterns.hpp"

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

// ----------------------------------------------------------------------------------------- 1. pure patterns

/// One pattern written in physical terms (independently of the Legendre basis), with the six named values expected.
struct PureCase {
  const char* name;
  Field field;
  std::array<double, 6> expected; // offset, profile slope, helix slope, twist, profile crowning, helix crowning
};

// Physical forms: a slope f_H rises by f_H across its range; a twist T makes the helix slope at the tip exceed that at
// the root by T; a crowning C is a parabola C(1 − u²) (ends 0, middle C), whose mean over the range is 2C/3 — the
// offset is the mean level of the flank, so it reads 2C/3 for a pure crowning.
const PureCase kPureCases[] = {
    {"Offset", [](double, double) { return 4.2; }, {4.2, 0, 0, 0, 0, 0}},
    {"ProfileSlope", [](double u, double) { return -7.0 * (u / 2.0); }, {0, -7.0, 0, 0, 0, 0}},
    {"HelixSlope", [](double, double w) { return 5.5 * (w / 2.0); }, {0, 0, 5.5, 0, 0, 0}},
    {"Twist", [](double u, double w) { return 6.0 * (u / 2.0) * (w / 2.0); }, {0, 0, 0, 6.0, 0, 0}},
    {"ProfileCrowning", [](double u, double) { return 3.0 * (1.0 - u * u); }, {2.0, 0, 0, 0, 3.0, 0}},
    {"HelixCrowning", [](double, double w) { return -4.5 * (1.0 - w * w); }, {-3.0, 0, 0, 0, 0, -4.5}},
    {"AllTogether",
     [](double u, double w) {
       return 1.0 - 7.0 * u / 2 + 5.5 * w / 2 + 6.0 * u * w / 4 + 3.0 * (1 - u * u) - 4.5 * (1 - w * w);
     },
     {1.0 + 2.0 - 3.0, -7.0, 5.5, 6.0, 3.0, -4.5}},
};


class PurePattern : public ::testing::TestWithParam<std::tuple<int, int>> {
protected:
  const PureCase& pure() const { return kPureCases[std::get<0>(GetParam())]; }
  GridSize size() const { return kGrids[std::get<1>(GetParam())]; }
};

TEST_P(PurePattern, IsRecoveredExactlyWithoutNoise) {
  const auto f = grid(size().nxi, size().nz, pure().field);
  const auto p = fit_flank_patterns(f, with_noise(1.0));
  for (std::size_t k = 0; k < 6; ++k)
    EXPECT_NEAR(pattern_value(p, kNamedPatterns[k]).value, pure().expected[k], 1e-9) << to_string(kNamedPatterns[k]);
  EXPECT_LT(p.rms_unexplained_um, 1e-9);
  EXPECT_FALSE(p.waviness_helix.wave.has_value());
  EXPECT_FALSE(p.waviness_profile.wave.has_value());
  EXPECT_EQ(p.points_used, f.points.size());
}

TEST_P(PurePattern, IsRecoveredWithinThreeStandardErrorsWithNoise) {
  const double sigma = 0.8;
  const auto f = grid(size().nxi, size().nz, pure().field, sigma, 20240611 + std::get<0>(GetParam()));
  const auto p = fit_flank_patterns(f, with_noise(sigma));
  for (std::size_t k = 0; k < 6; ++k) {
    const Estimate e = pattern_value(p, kNamedPatterns[k]);
    EXPECT_GT(e.standard_error, 0.0);
    EXPECT_NEAR(e.value, pure().expected[k], 3.0 * e.standard_error) << to_string(kNamedPatterns[k]);
  }
  EXPECT_NEAR(p.chi2_per_dof, 1.0, 0.5);
}

INSTANTIATE_TEST_SUITE_P(, PurePattern,
                         ::testing::Combine(::testing::Range(0, static_cast<int>(std::size(kPureCases))),
                                            ::testing::Range(0, 2)),
                         [](const auto& info) {
                           const GridSize g = kGrids[std::get<1>(info.param)];
                           return std::string(kPureCases[std::get<0>(info.param)].name) + "_" +
                                  std::to_string(g.nxi) + "x" + std::to_string(g.nz);
                         });

TEST(Patterns, StandardErrorsMatchTheScatterOverManySeeds) {
  // 400 noisy copies of the same field on the 7 × 9 grid: the standard deviation of each fitted pattern must agree
  // with its reported standard error (sampling error of a standard deviation from 400 values ≈ 3.5 %; allowed 15 %).
  const double sigma = 1.0;
  const Field field = [](double u, double w) { return 2.0 + u - 0.5 * w * w; };
  std::array<double, 6> sum{}, sum_sq{}, se{};
  const int runs = 400;
  for (int s = 0; s < runs; ++s) {
    const auto p = fit_flank_patterns(grid(7, 9, field, sigma, 1000 + s), with_noise(sigma));
    for (std::size_t k = 0; k < 6; ++k) {
      const Estimate e = pattern_value(p, kNamedPatterns[k]);
      sum[k] += e.value;
      sum_sq[k] += e.value * e.value;
      se[k] = e.standard_error;
    }
  }
  for (std::size_t k = 0; k < 6; ++k) {
    const double mean = sum[k] / runs, sd = std::sqrt((sum_sq[k] - runs * mean * mean) / (runs - 1));
    EXPECT_NEAR(sd / se[k], 1.0, 0.15) << to_string(kNamedPatterns[k]);
  }
}

TEST(Patterns, StandardErrorsOnAThreeByThreeGridMatchTheHandCalculation) {
  // 3 × 3 grid at u, w ∈ {−1, 0, 1}, worked by hand. u, w and uw are orthogonal to everything else there:
  // SE(a1) = σ/√Σu² = σ/√6 → SE(profile slope) = 2σ/√6; SE(a3) = σ/√Σu²w² = σ/2 → SE(twist) = 2σ. The even part
  // a0 + a4 P2(u) + a5 P2(w) = b0 + b4 u² + b5 w² is a balanced additive fit: b4 has variance σ²/Σ(u² − 2/3)² = σ²/2,
  // so a4 = 2 b4/3 has 2σ²/9 and C_α = −1.5 a4 has σ²/2; a0 = mean(data) − (b4 + b5)/3 (the three terms
  // uncorrelated) has σ²/9 + 2 (σ²/2)/9 = 2σ²/9.
  const auto f = grid(3, 3, [](double, double) { return 0.0; });
  const double sigma = 0.6;
  const auto p = fit_flank_patterns(f, with_noise(sigma));
  EXPECT_NEAR(p.offset_um.standard_error, std::sqrt(2.0) * sigma / 3.0, 1e-12);
  EXPECT_NEAR(p.profile_slope_um.standard_error, 2.0 * sigma / std::sqrt(6.0), 1e-12);
  EXPECT_NEAR(p.twist_um.standard_error, 2.0 * sigma, 1e-12);
  EXPECT_NEAR(p.profile_crowning_um.standard_error, sigma / std::sqrt(2.0), 1e-12);
  EXPECT_FALSE(p.waviness_helix.scanned); // 3 axial positions: nothing to scan
}

TEST(Patterns, PointsOutsideTheRangesAreLeftOutAndCounted) {
  auto f = grid(7, 9, [](double u, double) { return 3.0 * u; });
  f.points.push_back({kXi1 + 2.0, 50.0, 1000.0}); // in the tip chamfer
  f.points.push_back({100.0, kZ0 - 3.0, -1000.0}); // beyond the datum-face end of L_β
  const auto p = fit_flank_patterns(f, with_noise(0.5));
  EXPECT_EQ(p.points_used, 63u);
  EXPECT_EQ(p.points_outside_range, 2u);
  EXPECT_NEAR(p.profile_slope_um.value, 6.0, 1e-9);
}

TEST(Patterns, DescriptionNamesEveryPattern) {
  const auto p = fit_flank_patterns(grid(7, 9, [](double, double) { return -2.0; }, 0.0, 1, 4, Flank::Left),
                                    with_noise(0.5));
  const std::string s = describe_patterns(p);
  EXPECT_NE(s.find("tooth 4, left flank"), std::string::npos) << s;
  for (NamedPattern n : kNamedPatterns) EXPECT_NE(s.find(to_string(n)), std::string::npos) << s;
  EXPECT_NE(s.find("thinner"), std::string::npos) << s;
  EXPECT_NE(s.find("no significant waviness"), std::string::npos) << s;
}

// ----------------------------------------------------------------------------------------- 1b. waviness

TEST(Waviness, SinusoidAlongTheFaceWidthIsFound) {
  // 2 µm, λ = 25 mm along z, first crest 2.785 mm after z0 (phase 0.7 rad), on top of an offset and a helix crowning,
  // with σ = 0.5 µm noise, on the 20 × 40 grid (axial spacing 3.46 mm, so λ_min = 6.9 mm).
  const double A = 2.0, lambda = 25.0, phi = 0.7, sigma = 0.5;
  const Field field = [&](double u, double w) {
    const double z = kZ0 + (w + 1.0) / 2.0 * kLb;
    return 1.5 + 2.0 * (1 - w * w) + 0.0 * u + A * std::cos(2 * kPi * (z - kZ0) / lambda - phi);
  };
  const auto p = fit_flank_patterns(grid(20, 40, field, sigma, 77), with_noise(sigma));
  ASSERT_TRUE(p.waviness_helix.scanned);
  ASSERT_TRUE(p.waviness_helix.wave.has_value());
  const Waviness& wv = *p.waviness_helix.wave;
  EXPECT_EQ(wv.direction, WaveDirection::Helix);
  EXPECT_NEAR(wv.wavelength_mm, lambda, 0.10 * lambda);
  EXPECT_NEAR(wv.amplitude_um.value, A, 0.15 * A);
  EXPECT_NEAR(wv.first_crest_mm, kZ0 + phi / (2 * kPi) * lambda, 1.0);
  EXPECT_GT(wv.variance_drop, 0.5);
  EXPECT_FALSE(p.waviness_profile.wave.has_value());
  // With the wave in the fit the other patterns are still right.
  EXPECT_NEAR(p.helix_crowning_um.value, 2.0, 3 * p.helix_crowning_um.standard_error + 0.05);
  EXPECT_NEAR(p.rms_unexplained_um, sigma, 0.1 * sigma);
}

TEST(Waviness, NoiseFreeSinusoidIsLocatedBetweenTheScanFrequencies) {
  // Without noise the joint fit at the true λ removes everything, so the refined maximum must sit on it: far closer
  // than the scan step (≈ 0.46 mm in λ at 25 mm for L_β 135 mm and oversampling 10).
  const double lambda = 23.7;
  const Field field = [&](double, double w) {
    const double z = kZ0 + (w + 1.0) / 2.0 * kLb;
    return 1.2 * std::sin(2 * kPi * (z - kZ0) / lambda);
  };
  const auto p = fit_flank_patterns(grid(20, 40, field), with_noise(0.5));
  ASSERT_TRUE(p.waviness_helix.wave.has_value());
  EXPECT_NEAR(p.waviness_helix.wave->wavelength_mm, lambda, 0.02);
  EXPECT_NEAR(p.waviness_helix.wave->amplitude_um.value, 1.2, 0.01);
  EXPECT_NEAR(p.waviness_helix.wave->phase_rad.value, kPi / 2, 0.01); // sin = cos(· − π/2)
}

TEST(Waviness, SinusoidAlongTheProfileIsFound) {
  // 1.5 µm, λ = 6 mm along ξ on the 20 × 40 grid (profile spacing 1.58 mm, λ_min 3.16 mm).
  const double A = 1.5, lambda = 6.0, sigma = 0.5;
  const Field field = [&](double u, double) {
    const double xi = kXi0 + (u + 1.0) / 2.0 * kLa;
    return A * std::sin(2 * kPi * (xi - kXi0) / lambda);
  };
  const auto p = fit_flank_patterns(grid(20, 40, field, sigma, 78), with_noise(sigma));
  ASSERT_TRUE(p.waviness_profile.wave.has_value());
  EXPECT_NEAR(p.waviness_profile.wave->wavelength_mm, lambda, 0.10 * lambda);
  EXPECT_NEAR(p.waviness_profile.wave->amplitude_um.value, A, 0.15 * A);
  EXPECT_FALSE(p.waviness_helix.wave.has_value());
  EXPECT_NE(describe_patterns(p).find("along the profile"), std::string::npos);
}

TEST(Waviness, NoneIsReportedOnPureNoise) {
  // 10 seeds × 2 grids × 2 directions, each with a designed false-alarm probability of α = 1e-3.
  const double sigma = 1.0;
  for (const GridSize g : kGrids)
    for (std::uint64_t seed = 500; seed < 510; ++seed) {
      const auto p = fit_flank_patterns(grid(g.nxi, g.nz, [](double, double) { return 0.0; }, sigma, seed),
                                        with_noise(sigma));
      EXPECT_TRUE(p.waviness_helix.scanned);
      EXPECT_TRUE(p.waviness_profile.scanned);
      EXPECT_FALSE(p.waviness_helix.wave.has_value()) << g.nxi << "x" << g.nz << " seed " << seed << " λ "
                                                      << p.waviness_helix.best_wavelength_mm;
      EXPECT_FALSE(p.waviness_profile.wave.has_value()) << g.nxi << "x" << g.nz << " seed " << seed;
      EXPECT_LT(p.waviness_helix.best_chi2, p.waviness_helix.chi2_threshold);
    }
}

TEST(Waviness, ScanLimitsAndThresholdFollowTheStatedRule) {
  const auto p = fit_flank_patterns(grid(20, 40, [](double, double) { return 0.0; }, 1.0, 3), with_noise(1.0));
  const WavinessScan& s = p.waviness_helix;
  const double spacing = kLb / 39.0;
  EXPECT_NEAR(s.min_wavelength_mm, 2.0 * spacing, 1e-9);
  EXPECT_NEAR(s.max_wavelength_mm, kLb, 1e-12);
  const double M = 2.0 * std::ceil(kLb * (1.0 / (2.0 * spacing) - 1.0 / kLb) - 1e-9); // 2 × 19
  EXPECT_EQ(s.independent_wavelengths, static_cast<std::size_t>(M));
  EXPECT_NEAR(s.chi2_threshold, 2.0 * std::log(M / 1e-3), 1e-9);
}

} // namespace
