// Profile and helix deviations of synthetic traces with known answers (ISO 1328-1:2013 clause 3, docs/iso1328.md).
// Every case runs for the profile and the helix trace of a left and a right flank, through evaluate_gear.
// Units: mm (positions), µm (deviations).
#include "eval_fixtures.hpp"

#include "geartopo/evaluation/trace.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <ostream>
#include <random>
#include <string>
#include <tuple>

using namespace geartopo::evaluation;
using geartopo::Flank;
using namespace geartopo::evaluation::test;

namespace geartopo::evaluation {
// Readable parameter values in test listings.
void PrintTo(Flank s, std::ostream* os) { *os << to_string(s); }
} // namespace geartopo::evaluation

namespace {

enum class Kind { Profile, Helix };
void PrintTo(Kind k, std::ostream* os) { *os << (k == Kind::Profile ? "profile" : "helix"); }

class SyntheticTrace : public ::testing::TestWithParam<std::tuple<Kind, Flank>> {
protected:
  Kind kind() const { return std::get<0>(GetParam()); }
  Flank side() const { return std::get<1>(GetParam()); }
  double start() const { return kind() == Kind::Profile ? kProfileStart : kHelixStart; }
  double end() const { return kind() == Kind::Profile ? kProfileEnd : kHelixEnd; }
  double length() const { return end() - start(); }

  /// Puts `t` into the profile or helix slot of tooth 3 (the other trace is flat), evaluates the gear and returns the
  /// deviations of `t`.
  TraceDeviations evaluate(const Trace& t) const {
    FlankMeasurement f;
    f.tooth = 3;
    f.side = side();
    f.profile = kind() == Kind::Profile ? t : flat(kProfileStart, kProfileEnd);
    f.helix = kind() == Kind::Helix ? t : flat(kHelixStart, kHelixEnd);
    GearMeasurement m;
    m.flanks.push_back(f);
    // The trace's own values (normal, rise towards increasing position): direction and sign rules are tested in
    // test_iso_conventions.cpp.
    m.conventions = {IsoDirection::Normal, HelixSlopeSign::RiseTowardsPlusZ, scene_gear().beta_b};
    const GearEvaluation r = evaluate_gear(m, scene_gear().parameters());
    EXPECT_EQ(r.flanks.size(), 1u);
    EXPECT_EQ(r.flanks[0].side, side());
    return kind() == Kind::Profile ? r.flanks[0].profile : r.flanks[0].helix;
  }
};

std::string name(const ::testing::TestParamInfo<SyntheticTrace::ParamType>& info) {
  return std::string(std::get<0>(info.param) == Kind::Profile ? "Profile" : "Helix") +
         (std::get<1>(info.param) == Flank::Left ? "Left" : "Right");
}

} // namespace

// A pure slope s (µm/mm): f_H = s·L, F = |f_H|, f_f = 0. Material increasing towards increasing position (tip /
// away from the datum face) gives a positive f_H.
TEST_P(SyntheticTrace, PureSlope) {
  for (const double s : {0.05, -0.08}) {
    const double s0 = start();
    const auto r = evaluate(sampled([&](double x) { return 1.7 + s * (x - s0); }, start(), end(), 101, 5));
    EXPECT_NEAR(r.slope_um, s * length(), 1e-9);
    EXPECT_NEAR(r.total_um, std::abs(s) * length(), 1e-9);
    EXPECT_NEAR(r.form_um, 0.0, 1e-9);
    EXPECT_EQ(r.slope_um > 0, s > 0);
    EXPECT_EQ(r.points_in_range, 101u);
  }
}

// Parabola y = c (x − start)² on [0, L]. The least-squares line of c·u² on [0, L] is c (L u − L²/6); the residual
// c (u² − L u + L²/6) is L²c/6 at both ends and −L²c/12 at the middle, so f_f = c L²/4, f_H = c L² and F = c L².
// (The sampled polyline gives the same: with odd n the middle is a point, and the chord bumps shift the line without
// tilting it on a symmetric grid.)
TEST_P(SyntheticTrace, ParabolaFormIsAQuarterOfItsRise) {
  for (const double c : {0.002, -0.0015}) {
    const double s0 = start(), L = length();
    const auto r = evaluate(sampled([&](double x) { return c * (x - s0) * (x - s0); }, start(), end(), 201, 4));
    const double tol = 1e-9 * std::abs(c) * L * L;
    EXPECT_NEAR(r.form_um, std::abs(c) * L * L / 4.0, tol);
    EXPECT_NEAR(r.slope_um, c * L * L, tol);
    EXPECT_NEAR(r.total_um, std::abs(c) * L * L, tol);
  }
}

// A sine of amplitude A and k whole periods over the range, sampled at 40 points per period (peaks are points):
// F = 2A. The least-squares line of A sin(2πk u/L) on [0, L] has the rise −6A/(πk) (∫u sin = −L/ω), which is the
// stated bound on f_H; the residual then lies within 2A ± |f_H|.
TEST_P(SyntheticTrace, SineOfManyPeriods) {
  const double A = 2.0;
  const int k = 25;
  const double s0 = start(), L = length();
  const auto r = evaluate(sampled([&](double x) { return A * std::sin(2 * kPi * k * (x - s0) / L); }, start(), end(),
                                  40 * k + 1, 3));
  const double bound = 6.0 * A / (kPi * k); // 0.153 µm
  EXPECT_NEAR(r.total_um, 2.0 * A, 1e-9);
  EXPECT_LE(std::abs(r.slope_um), 1.01 * bound);
  EXPECT_NEAR(r.slope_um, -bound, 0.01 * bound); // the exact rise, within the chord error of 40 points per period
  EXPECT_GE(r.form_um, 2.0 * A - std::abs(r.slope_um) - 1e-9);
  EXPECT_LE(r.form_um, 2.0 * A + std::abs(r.slope_um) + 1e-9);
}

// Points outside the range are ignored: wild values beyond the range ends change nothing when the ends are points,
// and when the ends fall between points only the two bracketing points matter (linear interpolation).
TEST_P(SyntheticTrace, PointsOutsideTheRangeAreIgnored) {
  const double s = 0.04, s0 = start(), e0 = end(), L = length();
  // Range ends on points; every point outside is wild.
  Trace t = sampled([&](double x) { return (x < s0 || x > e0) ? 500.0 : s * (x - s0); }, start(), end(), 81, 6);
  auto r = evaluate(t);
  EXPECT_NEAR(r.slope_um, s * L, 1e-9);
  EXPECT_NEAR(r.total_um, s * L, 1e-9);
  EXPECT_NEAR(r.form_um, 0.0, 1e-9);
  EXPECT_EQ(r.points_in_range, 81u);

  // Range ends 0.3 spacings inside the outermost points; the bracketing points are on the line, the rest wild.
  const double h = L / 80;
  t = sampled([&](double x) { return (x < s0 - 1.5 * h || x > e0 + 1.5 * h) ? -300.0 : s * (x - s0); }, start() - h,
              end() + h, 83, 6);
  t.range_start_mm = start() - 0.7 * h; // between the points at start − h and start
  t.range_end_mm = end() + 0.7 * h;
  r = evaluate(t);
  EXPECT_NEAR(r.slope_um, s * (L + 1.4 * h), 1e-9);
  EXPECT_NEAR(r.total_um, s * (L + 1.4 * h), 1e-9);
  EXPECT_NEAR(r.form_um, 0.0, 1e-9);
  EXPECT_EQ(r.points_in_range, 81u);
}

// Uniform noise in [−a, a] (σ = a/√3; std::mt19937 is fully specified, so the data are the same everywhere) on a
// slope s. The slope estimate is linear in the data with weights ≈ those of a discrete fit on n equally spaced
// points, so σ(f_H) ≈ σ √(12/(n − 1)); we require |f_H − s L| ≤ 3 σ √(12/(n − 1)). The form deviation grows from 0
// to about the noise range 2a: it cannot exceed 2a plus twice the mean line's largest error, and with 601 samples
// the noise range is above 1.5a (probability of less ≈ 601 · 0.875^600 ≈ 0).
TEST_P(SyntheticTrace, NoiseRaisesFormButNotSlope) {
  const double s = 0.03, a = 0.8, sigma = a / std::sqrt(3.0);
  const int n = 601;
  const double s0 = start(), L = length();
  std::mt19937 rng(1328u + static_cast<unsigned>(kind() == Kind::Helix) * 7u + static_cast<unsigned>(side()));
  const auto noise = [&] { return a * (2.0 * ((static_cast<double>(rng()) + 0.5) / 4294967296.0) - 1.0); };
  Trace clean = sampled([&](double x) { return s * (x - s0); }, start(), end(), n);
  Trace noisy = clean;
  for (auto& y : noisy.deviation_um) y += noise();

  const auto rc = evaluate(clean), rn = evaluate(noisy);
  const double slope_bound = 3.0 * sigma * std::sqrt(12.0 / (n - 1)); // 0.0554 µm
  EXPECT_NEAR(rn.slope_um, s * L, slope_bound);
  const double line_error = std::abs(rn.mean_line_mid_um - s * L / 2) + std::abs(rn.slope_um - s * L) / 2;
  EXPECT_GT(rn.form_um, rc.form_um + 1.5 * a - 2 * line_error);
  EXPECT_LE(rn.form_um, 2.0 * a + 2.0 * line_error + 1e-12);
  EXPECT_GT(rn.total_um, rc.total_um);
}

INSTANTIATE_TEST_SUITE_P(ProfileAndHelixBothSides, SyntheticTrace,
                         ::testing::Combine(::testing::Values(Kind::Profile, Kind::Helix),
                                            ::testing::Values(Flank::Left, Flank::Right)),
                         name);

// The mean line is the least-squares line of the polyline, not of the points: crowding points into one half of the
// range does not pull it. Parabola c u² with 401 points on [0, L/2] and 21 on [L/2, L]: the chord bumps of the coarse
// half (height ≤ c h²/4, h = L/40) move f_H by less than 3e-4 c L² (a fit to the points alone would be off by about 28 %).
TEST(TraceEvaluation, MeanLineDoesNotDependOnSamplingDensity) {
  const double c = 0.002, L = 100.0;
  Trace t;
  t.range_start_mm = 0.0;
  t.range_end_mm = L;
  for (int i = 0; i <= 400; ++i) t.position_mm.push_back(0.5 * L * i / 400);
  for (int i = 1; i <= 20; ++i) t.position_mm.push_back(0.5 * L + 0.5 * L * i / 20);
  for (double x : t.position_mm) t.deviation_um.push_back(c * x * x);
  const auto r = evaluate_trace(t);
  EXPECT_NEAR(r.slope_um, c * L * L, 3e-4 * c * L * L);
  EXPECT_NEAR(r.form_um, c * L * L / 4, 3e-4 * c * L * L);
}

TEST(TraceEvaluation, RefusesBadTraces) {
  const auto refused = [](const Trace& t, const std::string& needle) {
    try {
      evaluate_trace(t);
      ADD_FAILURE() << "accepted; expected a refusal mentioning '" << needle << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  const Trace good = sampled([](double x) { return x; }, 0.0, 10.0, 11);
  ASSERT_NO_THROW(evaluate_trace(good));

  Trace t = good;
  t.range_start_mm = 4.5;
  t.range_end_mm = 6.5; // points 5 and 6 only
  refused(t, "2 point(s) inside");
  t.range_end_mm = 7.0; // 5, 6, 7: enough
  EXPECT_NO_THROW(evaluate_trace(t));

  t = good;
  t.deviation_um[4] = std::numeric_limits<double>::quiet_NaN();
  refused(t, "not finite");
  t = good;
  t.position_mm[6] = std::numeric_limits<double>::infinity();
  refused(t, "not finite");
  t = good;
  t.position_mm[5] = t.position_mm[4];
  refused(t, "strictly increasing");
  t = good;
  std::swap(t.position_mm[2], t.position_mm[3]);
  refused(t, "strictly increasing");
  t = good;
  t.deviation_um.pop_back();
  refused(t, "11 positions but 10 deviations");
  t = good;
  t.range_end_mm = 12.0;
  refused(t, "before the evaluation range end");
  t = good;
  t.range_start_mm = -1.0;
  refused(t, "after the evaluation range start");
  t = good;
  t.range_start_mm = t.range_end_mm = 5.0;
  refused(t, "empty evaluation range");
}

// A trace refused inside evaluate_gear names its flank and trace.
TEST(TraceEvaluation, GearEvaluationNamesTheRefusedTrace) {
  FlankMeasurement f;
  f.tooth = 4;
  f.side = Flank::Left;
  f.profile = flat(kProfileStart, kProfileEnd);
  f.helix = flat(kHelixStart, kHelixEnd);
  f.helix.deviation_um[2] = std::numeric_limits<double>::quiet_NaN();
  GearMeasurement m;
  m.flanks.push_back(f);
  try {
    evaluate_gear(m, scene_gear().parameters());
    ADD_FAILURE() << "accepted a NaN";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tooth 4 left flank, helix"), std::string::npos) << e.what();
  }
}
