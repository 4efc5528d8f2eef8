// Residual patterns, tooth trends, failing regions and summary statistics on synthetic residual fields with known
// answers (docs/residual-patterns.md). Units: ξ, z, wavelengths mm; residuals, patterns, σ µm; angles rad.
//
// Noise is Gaussian from std::mt19937_64 + Box–Muller written out here (std::normal_distribution is implementation-
// defined), so every seeded case gives the same numbers on every standard library.
#include "geartopo/evaluation/residual_patterns.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace geartopo::evaluation;
using geartopo::Flank;

namespace {

constexpr double kPi = std::numbers::pi;
// Evaluation ranges of a large helical gear flank (the default scene gear has m_n 14, b 150): L_α 30 mm, L_β 135 mm.
constexpr double kXi0 = 95.0, kXi1 = 125.0, kZ0 = 7.5, kZ1 = 142.5;
constexpr double kLa = kXi1 - kXi0, kLb = kZ1 - kZ0;

/// Reproducible standard normal deviates.
class Gauss {
public:
  explicit Gauss(std::uint64_t seed) : g_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = 0.0;
    do u1 = uniform(); while (u1 <= 0.0);
    const double u2 = uniform(), r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * kPi * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * kPi * u2);
  }
  double uniform() { return static_cast<double>(g_() >> 11) * 0x1.0p-53; }

private:
  std::mt19937_64 g_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

/// A residual field given as a function of (u, w), the normalised coordinates in [−1, 1].
using Field = std::function<double(double u, double w)>;

double u_of(double xi) { return 2.0 * (xi - kXi0) / kLa - 1.0; }
double w_of(double z) { return 2.0 * (z - kZ0) / kLb - 1.0; }

/// nxi roll lengths × nz axial positions spanning L_α × L_β exactly (rows root → tip, columns from the datum face),
/// residual = field + σ·N(0, 1) (σ = 0: no noise).
FlankResiduals grid(int nxi, int nz, const Field& field, double sigma = 0.0, std::uint64_t seed = 1, int tooth = 1,
                    Flank side = Flank::Right) {
  FlankResiduals f{tooth, side, {}, kXi0, kXi1, kZ0, kZ1};
  Gauss noise(seed);
  for (int i = 0; i < nxi; ++i)
    for (int k = 0; k < nz; ++k) {
      const double xi = kXi0 + kLa * i / (nxi - 1), z = kZ0 + kLb * k / (nz - 1);
      const double r = field(u_of(xi), w_of(z)) + (sigma > 0 ? sigma * noise() : 0.0);
      f.points.push_back({xi, z, r});
    }
  return f;
}

PatternOptions with_noise(double sigma) {
  PatternOptions o;
  o.noise_um = sigma;
  return o;
}

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

struct GridSize {
  int nxi, nz;
};
const GridSize kGrids[] = {{7, 9}, {20, 40}};

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

// ----------------------------------------------------------------------------------------- 3. failing regions

RegionOptions region_options(double sigma, double k = 3.0) {
  RegionOptions o;
  o.noise_um = sigma;
  o.k = k;
  return o;
}

bool contains(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }

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
