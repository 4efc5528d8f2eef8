// Gear geometry against independent published worked examples, and the identities ISO 21771 implies.
#include "gear_fixtures.hpp"

#include "geartopo/core/field_error.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/gears/involute.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace geartopo;
using geartopo::test::kDeg;
using geartopo::test::make_spec;

TEST(Involute, InverseRoundTrip) {
  for (double a = 0.01; a < 1.3; a += 0.01) EXPECT_NEAR(gears::inverse_involute(gears::involute(a)), a, 1e-12);
  EXPECT_NEAR(gears::involute(20.0 * kDeg), 0.014904383867336446, 1e-15); // inv 20° (tables: 0.0149044)
}

// SDP/SI, "Elements of Metric Gear Technology", Section 10, Table 10-3 (helical, normal system):
// m_n = 5, α_n = 20°, β = 25°, z = 16, x_n = +0.2 → h_a = 6.0000, s_n = 8.5819.
TEST(GearGeometry, SdpSiTable10_3HelicalToothThickness) {
  const gears::GearGeometry g(make_spec(5.0, 16, 20.0, 25.0, 0.2));
  EXPECT_NEAR(g.normal_tooth_thickness_mm(), 8.5819, 5e-5);
  EXPECT_NEAR(0.5 * (g.tip_diameter_mm() - g.reference_diameter_mm()), 6.0000, 5e-5);
  // The normal thickness at the reference diameter, computed through the transverse section, is s_n again.
  EXPECT_NEAR(g.normal_tooth_thickness_at(g.reference_diameter_mm()), g.normal_tooth_thickness_mm(), 1e-10);
}

// SDP/SI, same document, Table 10-1 (spur): m = 10, α = 20°, z = 12, x = +0.3 → s = 17.8918.
TEST(GearGeometry, SdpSiTable10_1SpurToothThickness) {
  const gears::GearGeometry g(make_spec(10.0, 12, 20.0, 0.0, 0.3));
  EXPECT_NEAR(g.normal_tooth_thickness_mm(), 17.8918, 5e-5);
}

// MESYS AG, "Calculation of geometry for helical gear", default example (z = 20, m_n = 1, α_n = 20°, β = 0, x = 0,
// d_a = 22, d_f = 17.5, tool root radius 0.25 m_n): d = 20, d_b = 18.7939, s_n = 1.5708, s_an = 0.6949,
// d_Ff = 18.8003, k = 2 → W_k = 4.7083 touching at d_MSpan = 19.3746.
TEST(GearGeometry, MesysSpurExample) {
  auto s = make_spec(1.0, 20, 20.0, 0.0, 0.0);
  s.tip_diameter_mm = 22.0;
  s.root_diameter_mm = 17.5;
  s.rack_root_radius_coef = 0.25;
  const gears::GearGeometry g(s);
  EXPECT_NEAR(g.reference_diameter_mm(), 20.0, 1e-12);
  EXPECT_NEAR(g.base_diameter_mm(), 18.7939, 5e-5);
  EXPECT_NEAR(g.normal_tooth_thickness_mm(), 1.5708, 5e-5);
  EXPECT_NEAR(g.tip_normal_thickness_mm(), 0.6949, 5e-5);
  EXPECT_NEAR(g.root_form_diameter_mm(), 18.8003, 5e-5);
  EXPECT_NEAR(g.base_tangent_length_mm(2), 4.7083, 5e-5);
  EXPECT_NEAR(g.span_contact_diameter_mm(2), 19.3746, 5e-5);
}

// machinecalcs.com span calculator: m = 2, z = 20, α = 20° → k = 3, W_3 = 15.321, W_4 = 21.225.
// (MESYS chooses k = 2 for the same z; the DIN 3960 / DIN 21773 rule gives 3.)
TEST(GearGeometry, SpurSpanMeasurementAndCustomaryK) {
  const gears::GearGeometry g(make_spec(2.0, 20, 20.0, 0.0, 0.0));
  EXPECT_EQ(g.span_teeth(), 3);
  EXPECT_NEAR(g.base_tangent_length_mm(3), 15.321, 5e-4);
  EXPECT_NEAR(g.base_tangent_length_mm(4), 21.225, 5e-4);
}

// ISO/TR 6336-30:2022 Annex A, Example 1 (as transcribed in public test data; W_k1 = 38.196 mm, Table A.1 p. 43,
// gives x_E1 = 0.11779, p. 45): m_n = 8, z = 17, α_n = 20°, β = 15.8° left hand, k = 2.
TEST(GearGeometry, IsoTr6336_30HelicalBaseTangentLength) {
  const gears::GearGeometry g(make_spec(8.0, 17, 20.0, -15.8, 0.11779, 100.0));
  EXPECT_NEAR(g.base_tangent_length_mm(2), 38.196, 1e-3);
  EXPECT_EQ(g.spec().hand(), gears::Hand::Left);
}

TEST(GearGeometry, HelicalRelations) {
  const gears::GearGeometry g(geartopo::test::paper_gear());
  const double beta = 30.0 * kDeg, an = 20.0 * kDeg;
  EXPECT_NEAR(g.reference_diameter_mm(), 35 * 14 / std::cos(beta), 1e-10);
  EXPECT_NEAR(std::tan(g.transverse_pressure_angle()), std::tan(an) / std::cos(beta), 1e-14);
  EXPECT_NEAR(std::tan(g.base_helix_angle()), std::tan(beta) * std::cos(g.transverse_pressure_angle()), 1e-14);
  EXPECT_NEAR(g.lead_mm(), std::numbers::pi * g.reference_diameter_mm() / std::tan(beta), 1e-9);
  // The lead is common to every cylinder: π d_b / tan β_b = π d / tan β.
  EXPECT_NEAR(std::numbers::pi * g.base_diameter_mm() / std::tan(g.base_helix_angle()), g.lead_mm(), 1e-8);
  // Normal base pitch is the same for the gear and its basic rack: p_bn = π m_n cos α_n.
  EXPECT_NEAR(g.normal_base_pitch_mm(), std::numbers::pi * 14 * std::cos(an), 1e-10);
  // The seed gear: d = 565.80 mm as ISO 1328 uses it in the tolerance formulas.
  EXPECT_NEAR(g.reference_diameter_mm(), 565.80, 5e-3);
}

TEST(GearGeometry, SpurLeadIsInfinite) {
  const gears::GearGeometry g(make_spec(3.0, 30, 20.0, 0.0, 0.0));
  EXPECT_TRUE(std::isinf(g.lead_mm()));
  EXPECT_EQ(g.twist_rad_per_mm(), 0.0);
}

// W_k spans (k − 1) base pitches plus one base tooth thickness, measured normal to the base helix: an identity
// between W_k and the tooth-thickness function, checked for several gears.
TEST(GearGeometry, BaseTangentLengthMatchesToothThickness) {
  for (const auto& s : {make_spec(14, 35, 20, 30, 0.274), make_spec(3, 24, 20, -25, 0.4), make_spec(2, 20, 20, 0, 0),
                        make_spec(5, 60, 25, 12, -0.3)}) {
    const gears::GearGeometry g(s);
    const double sbt = g.transverse_tooth_thickness_at(g.base_diameter_mm()); // arc on the base circle
    for (int k = 1; k < 6; ++k) {
      const double w = std::cos(g.base_helix_angle()) * ((k - 1) * g.transverse_base_pitch_mm() + sbt);
      EXPECT_NEAR(g.base_tangent_length_mm(k), w, 1e-9) << "z=" << s.teeth << " k=" << k;
    }
  }
}

// The customary k puts the caliper contact nearest to d + 2 x m_n: within a quarter of the roll-length step that
// one more tooth adds (p_bt cos² β_b / 2).
TEST(GearGeometry, CustomarySpanTouchesNearMidDepth) {
  for (const auto& s : {make_spec(14, 35, 20, 30, 0.274), make_spec(3, 24, 20, -25, 0.4), make_spec(2, 20, 20, 0, 0),
                        make_spec(5, 60, 25, 12, -0.3), make_spec(1, 100, 20, 35, 0.5)}) {
    const gears::GearGeometry g(s);
    const int k = g.span_teeth();
    const double xi_target = g.roll_length_at(g.reference_diameter_mm() + 2 * s.profile_shift * s.normal_module_mm);
    const double xi_k = g.roll_length_at(g.span_contact_diameter_mm(k));
    const double step = 0.5 * g.transverse_base_pitch_mm() * std::pow(std::cos(g.base_helix_angle()), 2);
    EXPECT_LE(std::abs(xi_k - xi_target), 0.5 * step + 1e-9) << "z=" << s.teeth;
  }
}

TEST(GearGeometry, PointedTipDiameterHasZeroThickness) {
  const gears::GearGeometry g(geartopo::test::paper_gear());
  EXPECT_NEAR(g.transverse_tooth_thickness_at(g.pointed_tip_diameter_mm()), 0.0, 1e-9);
  EXPECT_GT(g.tip_normal_thickness_mm(), 0.0);
}

namespace {
std::string failing_field(const gears::GearSpec& s) {
  try {
    gears::GearGeometry g(s);
  } catch (const FieldError& e) {
    return e.field();
  }
  return "";
}
} // namespace

// Classic undercut limit of a spur gear generated by a rack with h_aP0 = m and no tip radius: z_min = 2 / sin² α
// = 17.1, so 17 teeth are undercut and 18 are not.
TEST(GearGeometry, UndercutLimitIsTheClassicOne) {
  auto s = make_spec(1.0, 17, 20.0, 0.0, 0.0);
  s.rack_dedendum_coef = 1.0;
  s.rack_root_radius_coef = 0.0;
  s.root_diameter_mm = 17.0 - 2.1; // below the rack's reach (d − 2 h_fP)
  EXPECT_LT(2.0 / std::pow(std::sin(20 * kDeg), 2), 18.0);
  EXPECT_GT(2.0 / std::pow(std::sin(20 * kDeg), 2), 17.0);
  EXPECT_EQ(failing_field(s), "gear.profile_shift");
  s.teeth = 18;
  s.tip_diameter_mm = gears::conventional_tip_diameter(s);
  s.root_diameter_mm = 18.0 - 2.1;
  EXPECT_EQ(failing_field(s), "");
}

TEST(GearGeometry, DegenerateGearsAreRefusedNamingTheField) {
  auto base = make_spec(2.0, 30, 20.0, 15.0, 0.0);
  auto s = base;
  s.normal_module_mm = 0.0;
  EXPECT_EQ(failing_field(s), "gear.normal_module_mm");
  s = base;
  s.normal_module_mm = -1.0;
  EXPECT_EQ(failing_field(s), "gear.normal_module_mm");
  s = base;
  s.teeth = 4;
  EXPECT_EQ(failing_field(s), "gear.teeth");
  s = base;
  s.helix_angle_rad = 45.0 * kDeg;
  EXPECT_EQ(failing_field(s), "gear.helix_angle_deg");
  s.helix_angle_rad = -50.0 * kDeg;
  EXPECT_EQ(failing_field(s), "gear.helix_angle_deg");
  s = make_spec(2.0, 8, 20.0, 0.0, 0.0); // z = 8, x = 0: undercut
  EXPECT_EQ(failing_field(s), "gear.profile_shift");
  s = base;
  s.tip_diameter_mm = 75.0; // far beyond the pointed-tip diameter of this 62 mm gear
  EXPECT_EQ(failing_field(s), "gear.tip_diameter_mm");
  s = base;
  s.root_diameter_mm = s.tip_diameter_mm + 1.0;
  EXPECT_EQ(failing_field(s), "gear.root_diameter_mm");
  s = base;
  s.face_width_mm = 0.0;
  EXPECT_EQ(failing_field(s), "gear.face_width_mm");
  s = base;
  s.profile_shift = std::nan("");
  EXPECT_EQ(failing_field(s), "gear.profile_shift");
}

TEST(GearGeometry, ThinTipIsAWarningNotAnError) {
  auto s = make_spec(2.0, 12, 20.0, 0.0, 0.6); // large shift on few teeth: tip gets thin but stays positive
  const gears::GearGeometry g(s);
  ASSERT_GT(g.tip_normal_thickness_mm(), 0.0);
  ASSERT_LT(g.tip_normal_thickness_mm(), 0.25 * 2.0);
  ASSERT_EQ(g.warnings().size(), 1u);
  EXPECT_NE(g.warnings()[0].find("thin tip"), std::string::npos);
}
