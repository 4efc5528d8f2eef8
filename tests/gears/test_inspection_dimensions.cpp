// Tooth-thickness inspection dimensions (W_k, M_dK) with allowances: published worked examples, and for helical
// gears an independent placement of the ball against the exact involute helicoid.
#include "gear_fixtures.hpp"

#include "geartopo/core/field_error.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/gears/involute.hpp"
#include "geartopo/gears/involute_helicoid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace geartopo;
using geartopo::test::kDeg;
using geartopo::test::make_spec;

namespace {
constexpr double kPi = std::numbers::pi;
}

// MESYS AG, "Calculation of geometry for helical gear" (mesys.ag/calc/helicalgear.fcgi), default example:
// z = 20, m_n = 1, α_n = 20°, β = 0, x = 0, D_M = 1.7 → M_dK = 22.2941, d_M (ball contact) = 19.9594.
// Printed to 0.1 µm: tolerance half a digit. (The same page prints M_rK = 11.1471, where M_dK/2 = 11.14705 rounds to
// 11.1470: 0.05 µm beyond its last digit, so MESYS must round or compute M_rK differently; not asserted.)
TEST(InspectionDimensions, MesysSpurDimensionOverBalls) {
  auto s = make_spec(1.0, 20, 20.0, 0.0, 0.0);
  s.tip_diameter_mm = 22.0;
  s.root_diameter_mm = 17.5;
  s.rack_root_radius_coef = 0.25;
  const gears::GearGeometry g(s);
  EXPECT_NEAR(g.dimension_over_balls_mm(1.7), 22.2941, 5e-5);
  EXPECT_NEAR(g.ball_contact_diameter_mm(1.7), 19.9594, 5e-5);
  // MESYS's default ball for m = 1 is 1.7 mm; the customary rule (ideal ball rounded to 0.05 mm) gives the same.
  EXPECT_NEAR(g.customary_ball_diameter_mm(), 1.70, 1e-12);
  EXPECT_NEAR(g.ball_diameter_mm(), 1.70, 1e-12);
}

// MESYS AG, "ondrives" spur calculator (mesys.ch/calc/ondrives.fcgi): z = 30, m = 1, α = 20°, DIN 867 profile,
// A_sn = −0.0600 / −0.0300, D_M = 1.7 → s_n = 1.5108 / 1.5408, M_rK = 16.0821 / 16.1190 mm. Even z: M_dK = 2 M_rK.
TEST(InspectionDimensions, MesysSpurRadialBallDimensionWithAllowances) {
  auto s = make_spec(1.0, 30, 20.0, 0.0, 0.0);
  s.thickness_allowance_upper_mm = -0.03;
  s.thickness_allowance_lower_mm = -0.06;
  const gears::GearGeometry g(s);
  EXPECT_NEAR(g.normal_tooth_thickness_mm() + s.thickness_allowance_lower_mm, 1.5108, 5e-5);
  EXPECT_NEAR(g.normal_tooth_thickness_mm() + s.thickness_allowance_upper_mm, 1.5408, 5e-5);
  EXPECT_NEAR(0.5 * g.dimension_over_balls_mm(1.7, -0.06), 16.0821, 5e-5);
  EXPECT_NEAR(0.5 * g.dimension_over_balls_mm(1.7, -0.03), 16.1190, 5e-5);
}

// drgears.com, "pin diameter, external helical gears": m_n = 8, α_n = 20°, β = 15°, x = 0; the ideal ball touching
// near the reference circle is 13.5142 mm for z = 50 and 13.48797 mm for z = 61. drgears approximates through a
// "virtual spur gear"; geartopo solves the helical contact exactly, so the two agree to ~1.5 µm, far below the
// 50 µm step the ball is then rounded to.
TEST(InspectionDimensions, IdealBallMatchesDrGearsHelicalExamples) {
  EXPECT_NEAR(gears::GearGeometry(make_spec(8.0, 50, 20.0, 15.0, 0.0, 80.0)).ideal_ball_diameter_mm(), 13.5142, 2e-3);
  EXPECT_NEAR(gears::GearGeometry(make_spec(8.0, 61, 20.0, 15.0, 0.0, 80.0)).ideal_ball_diameter_mm(), 13.48797, 2e-3);
}

// W_k with an allowance: each flank moves by A_sn cos α_n / 2 along its normal, W_k spans two flanks, so
// ΔW_k = A_sn cos α_n exactly (DIN 21773 §14: "E*_W = cos α_n holds exactly for helical").
TEST(InspectionDimensions, SpanMeasurementShiftsByAllowanceTimesCosAlphaN) {
  const gears::GearGeometry g(make_spec(3.0, 31, 20.0, 15.0, 0.2, 40.0));
  const int k = g.span_teeth();
  EXPECT_NEAR(g.base_tangent_length_mm(k, -0.05) - g.base_tangent_length_mm(k), -0.05 * std::cos(20.0 * kDeg), 1e-9);
}

// Finite difference of M_dK against the closed-form sensitivity obtained by differentiating the inv α_Mt equation
// (written out here, not taken from the code): dM_dK/dA_sn = cos α_n / (sin α_Mt cos β_b) · [cos(90°/z) for odd z].
TEST(InspectionDimensions, DimensionOverBallsSensitivityToTheAllowance) {
  for (const int z : {30, 31}) {
    const gears::GearGeometry g(make_spec(3.0, z, 20.0, 15.0, 0.2, 40.0));
    const double D = 5.25, h = 1e-4;
    const double fd = (g.dimension_over_balls_mm(D, h) - g.dimension_over_balls_mm(D, -h)) / (2 * h);
    const double alpha_mt = std::acos(g.base_diameter_mm() / g.ball_centre_diameter_mm(D));
    double expected = std::cos(20.0 * kDeg) / (std::sin(alpha_mt) * std::cos(g.base_helix_angle()));
    if (z % 2 == 1) expected *= std::cos(0.5 * kPi / z);
    EXPECT_NEAR(fd, expected, 1e-6) << "z = " << z;
  }
}

namespace {

// Places a ball of diameter D in tooth space 1 (between tooth 1's right flank and tooth 2's left flank) in the
// transverse plane z0 using only the exact helicoid: bisection on the centre radius until the centre's normal
// distance from the flank is D/2. A thickness allowance is modelled independently of the closed form, as the same
// gear with a profile shift changed by A_sn / (2 m_n tan α_n) (same base cylinder, thinner tooth).
struct PlacedBall {
  double centre_radius_mm, contact_diameter_mm;
};

PlacedBall place_ball(const gears::GearGeometry& g, double D, double z0) {
  const gears::InvoluteHelicoid h(g);
  const double phi = h.tooth_centre_angle(1, z0) + kPi / g.teeth(); // middle of space 1
  auto distance = [&](double r) {
    const Eigen::Vector3d c(r * std::cos(phi), r * std::sin(phi), z0);
    const auto loc = h.locate_on(c, 1, Flank::Right);
    EXPECT_TRUE(loc.has_value());
    return *loc;
  };
  double lo = 0.5 * g.base_diameter_mm() + 1e-3, hi = 0.5 * g.tip_diameter_mm() + D;
  for (int i = 0; i < 200 && hi - lo > 1e-11; ++i) {
    const double mid = 0.5 * (lo + hi);
    (distance(mid).normal_distance_mm < 0.5 * D ? lo : hi) = mid;
  }
  const double r = 0.5 * (lo + hi);
  const auto loc = distance(r);
  // The ball is symmetric in the space: it touches tooth 2's left flank at the same distance.
  const gears::InvoluteHelicoid hh(g);
  const Eigen::Vector3d c(r * std::cos(phi), r * std::sin(phi), z0);
  const auto left = hh.locate_on(c, 2, Flank::Left);
  EXPECT_TRUE(left.has_value());
  EXPECT_NEAR(left->normal_distance_mm, 0.5 * D, 1e-8);
  return {r, loc.diameter_mm};
}

} // namespace

TEST(InspectionDimensions, HelicalBallPlacedOnTheExactHelicoidMatchesTheClosedForm) {
  struct Case {
    int z;
    double beta_deg, x, D, a_sn;
  };
  // Even and odd z, both hands, with and without profile shift and allowance (balls near the customary 1.75 m_n).
  for (const Case& c : {Case{50, 15.0, 0.0, 14.0, 0.0}, Case{61, 15.0, 0.0, 13.0, 0.0}, Case{31, -15.0, 0.2, 5.25, -0.08},
                        Case{30, 25.0, 0.3, 5.0, -0.12}, Case{30, 0.0, 0.0, 5.1, -0.05}}) {
    const double mn = c.z > 40 ? 8.0 : 3.0;
    const gears::GearGeometry g(make_spec(mn, c.z, 20.0, c.beta_deg, c.x, 60.0));
    auto thinner = g.spec();
    thinner.profile_shift += c.a_sn / (2.0 * mn * std::tan(20.0 * kDeg));
    const gears::GearGeometry gt(thinner);
    const PlacedBall ball = place_ball(gt, c.D, 30.0);
    // Two balls in one transverse plane, in spaces 1 and 1 + z/2 (even) or 1 + (z−1)/2 (odd).
    const int opposite = c.z / 2;
    const double angle = 2.0 * kPi * opposite / c.z;
    const double m_numeric = 2.0 * ball.centre_radius_mm * std::sin(0.5 * angle) + c.D;
    SCOPED_TRACE(::testing::Message() << "z = " << c.z << ", β = " << c.beta_deg << "°, A_sn = " << c.a_sn);
    EXPECT_NEAR(g.dimension_over_balls_mm(c.D, c.a_sn), m_numeric, 1e-5); // 0.01 µm
    EXPECT_NEAR(g.ball_contact_diameter_mm(c.D, c.a_sn), ball.contact_diameter_mm, 1e-5);
  }
}

TEST(InspectionDimensions, BadBallsAndAllowancesAreNamed) {
  auto s = make_spec(3.0, 31, 20.0, 15.0, 0.2, 40.0);
  s.ball_diameter_mm = 0.5; // sinks below the base circle
  try {
    gears::GearGeometry g(s);
    FAIL() << "a 0.5 mm ball in a m_n = 3 gear was accepted";
  } catch (const FieldError& e) {
    EXPECT_EQ(e.field(), "gear.ball_diameter_mm");
  }
  s.ball_diameter_mm.reset();
  s.thickness_allowance_upper_mm = -0.1;
  s.thickness_allowance_lower_mm = -0.05;
  try {
    gears::GearGeometry g(s);
    FAIL() << "A_sni above A_sne was accepted";
  } catch (const FieldError& e) {
    EXPECT_EQ(e.field(), "gear.thickness_allowance_lower_um");
  }
}
