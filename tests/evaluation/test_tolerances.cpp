// ISO 1328-1:2013 tolerances, rounding, validity and classes (docs/iso1328.md; check values from
// /work/shared/notes/iso1328.md). Units: mm (gear data), µm (tolerances).
#include "eval_fixtures.hpp"

#include "geartopo/evaluation/tolerances.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

using namespace geartopo::evaluation;
using geartopo::Flank;
using namespace geartopo::evaluation::test;

namespace {
GearParameters gear(double mn, double d, double b, int z = 30, double beta_deg = 0.0) {
  return {z, d, mn, b, deg(beta_deg)};
}
} // namespace

TEST(Tolerances, RoundingRule) {
  EXPECT_DOUBLE_EQ(round_tolerance_um(4.94), 4.9);
  EXPECT_DOUBLE_EQ(round_tolerance_um(4.96), 5.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(7.2), 7.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(7.3), 7.5);
  EXPECT_DOUBLE_EQ(round_tolerance_um(10.4), 10.0);
  // Ties round half up, although the decimal ties are not exact in binary (4.85 is stored below 4.85).
  EXPECT_DOUBLE_EQ(round_tolerance_um(4.95), 5.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(4.85), 4.9);
  EXPECT_DOUBLE_EQ(round_tolerance_um(0.15), 0.2);
  EXPECT_DOUBLE_EQ(round_tolerance_um(7.25), 7.5);
  EXPECT_DOUBLE_EQ(round_tolerance_um(7.75), 8.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(10.5), 11.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(36.5), 37.0);
  // Ties reached by arithmetic land just below the tie (1.2 + 0.15 = 1.3499999999999999) and still round up.
  EXPECT_DOUBLE_EQ(round_tolerance_um(1.2 + 0.15), 1.4);
  EXPECT_DOUBLE_EQ(round_tolerance_um(4.1 + 0.05), 4.2);
  // Band edges: 10 belongs to 5–10 (0.5 steps), 5 to 5–10, just below 5 to the 0.1 band.
  EXPECT_DOUBLE_EQ(round_tolerance_um(10.0), 10.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(9.76), 10.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(5.0), 5.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(5.2), 5.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(4.99), 5.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(1.04), 1.0);
  EXPECT_DOUBLE_EQ(round_tolerance_um(11.49), 11.0);
  EXPECT_THROW(round_tolerance_um(-1.0), std::invalid_argument);
  EXPECT_THROW(round_tolerance_um(NAN), std::invalid_argument);
}

// The check table of the shared note (rounded values).
TEST(Tolerances, CheckTableMn2D100B20Class5) {
  const auto t = tolerances(gear(2, 100, 20), 5);
  EXPECT_DOUBLE_EQ(t.f_pT_um, 6.0);
  EXPECT_DOUBLE_EQ(t.F_pT_um, 19.0);
  EXPECT_DOUBLE_EQ(t.f_HalphaT_um, 4.9);
  EXPECT_DOUBLE_EQ(t.f_falphaT_um, 6.0);
  EXPECT_DOUBLE_EQ(t.F_alphaT_um, 8.0);
  EXPECT_DOUBLE_EQ(t.f_HbetaT_um, 6.0);
  EXPECT_DOUBLE_EQ(t.f_fbetaT_um, 6.5);
  EXPECT_DOUBLE_EQ(t.F_betaT_um, 9.0);
}

TEST(Tolerances, CheckTableMn3D120B30Class6) {
  const auto t = tolerances(gear(3, 120, 30), 6);
  EXPECT_DOUBLE_EQ(t.f_pT_um, 9.0);
  EXPECT_DOUBLE_EQ(t.F_pT_um, 29.0);
  EXPECT_DOUBLE_EQ(t.f_HalphaT_um, 7.5);
  EXPECT_DOUBLE_EQ(t.f_falphaT_um, 9.5);
  EXPECT_DOUBLE_EQ(t.F_alphaT_um, 12.0);
  EXPECT_DOUBLE_EQ(t.f_HbetaT_um, 9.0);
  EXPECT_DOUBLE_EQ(t.f_fbetaT_um, 10.0);
  EXPECT_DOUBLE_EQ(t.F_betaT_um, 14.0);
}

// g = (√2)^(A − 5) applies to the unrounded class-5 value: two classes double it.
TEST(Tolerances, ClassStepIsRootTwoOnTheUnroundedValue) {
  const auto p = gear(2, 100, 20);
  for (int q = 0; q <= static_cast<int>(Quantity::Runout); ++q) {
    const auto qq = static_cast<Quantity>(q);
    EXPECT_NEAR(unrounded_tolerance_um(qq, p, 7), 2.0 * class5_tolerance_um(qq, p), 1e-12);
    EXPECT_NEAR(unrounded_tolerance_um(qq, p, 1), class5_tolerance_um(qq, p) / 4.0, 1e-12);
    for (int a = 2; a <= 11; ++a) EXPECT_GT(tolerance_um(qq, p, a), tolerance_um(qq, p, a - 1));
  }
  // f_HαT keeps its 0.001 d term (one public implementation drops it): 0.4·2 + 0.001·100 + 4 = 4.9.
  EXPECT_NEAR(class5_tolerance_um(Quantity::ProfileSlope, p), 4.9, 1e-12);
  EXPECT_THROW(tolerance_um(Quantity::SinglePitch, p, 0), std::invalid_argument);
  EXPECT_THROW(tolerance_um(Quantity::SinglePitch, p, 12), std::invalid_argument);
}

// The default scene (d = 565.80 mm, m_n = 14 mm, b = 150 mm), class 5, from the formulas by hand
// (√d = 23.7866, √b = 12.2474):
TEST(Tolerances, DefaultSceneClass5) {
  const GearParameters p{35, 565.80, 14.0, 150.0, deg(30.0)};
  struct Row {
    Quantity q;
    double unrounded, rounded;
  };
  const Row rows[] = {
      {Quantity::SinglePitch, 11.1658, 11.0},     // 0.5658 + 5.6 + 5
      {Quantity::CumulativePitch, 36.0142, 36.0}, // 1.1316 + 13.0826 + 9.8 + 12
      {Quantity::ProfileSlope, 10.1658, 10.0},    // 5.6 + 0.5658 + 4
      {Quantity::ProfileForm, 12.7, 13.0},        // 7.7 + 5
      {Quantity::ProfileTotal, 16.2676, 16.0},    // √(10.1658² + 12.7²) = √264.6335
      {Quantity::HelixSlope, 9.4759, 9.5},        // 1.1893 + 4.2866 + 4
      {Quantity::HelixForm, 11.1764, 11.0},       // 1.6651 + 5.5114 + 4
      {Quantity::HelixTotal, 14.6528, 15.0},      // √(9.4759² + 11.1764²) = √214.7055
      {Quantity::Runout, 32.4128, 32.0},          // 0.9 · 36.0142
  };
  for (const Row& r : rows) {
    EXPECT_NEAR(class5_tolerance_um(r.q, p), r.unrounded, 1e-4) << symbol(r.q);
    EXPECT_DOUBLE_EQ(tolerance_um(r.q, p, 5), r.rounded) << symbol(r.q);
  }
  const auto t = tolerances(p, 5);
  std::printf("default scene, class 5 (µm): f_pT %.1f  F_pT %.1f  f_HaT %.1f  f_faT %.1f  F_aT %.1f  f_HbT %.1f  "
              "f_fbT %.1f  F_bT %.1f  F_rT %.1f\n",
              t.f_pT_um, t.F_pT_um, t.f_HalphaT_um, t.f_falphaT_um, t.F_alphaT_um, t.f_HbetaT_um, t.f_fbetaT_um,
              t.F_betaT_um, t.F_rT_um);
}

// A value exactly at a class's rounded tolerance belongs to that class; a hair above it to the next.
TEST(Classification, ValueAtATolerance) {
  const auto p = gear(2, 100, 20);
  for (int q = 0; q <= static_cast<int>(Quantity::Runout); ++q) {
    const auto qq = static_cast<Quantity>(q);
    for (int a = 1; a <= 11; ++a) {
      const double t = tolerance_um(qq, p, a);
      EXPECT_EQ(tolerance_class(qq, t, p), a) << symbol(qq) << " class " << a;
      EXPECT_EQ(tolerance_class(qq, -t, p), a) << symbol(qq) << " class " << a << " (negative)";
      EXPECT_EQ(tolerance_class(qq, std::nextafter(t, 1e9), p), a + 1) << symbol(qq) << " class " << a;
    }
  }
  // Literal values from the check table: f_HαT(5) = 4.9, f_fβT(5) = 6.5.
  EXPECT_EQ(tolerance_class(Quantity::ProfileSlope, 4.9, p), 5);
  EXPECT_EQ(tolerance_class(Quantity::ProfileSlope, -4.9, p), 5);
  EXPECT_EQ(tolerance_class(Quantity::ProfileSlope, 4.91, p), 6);
  EXPECT_EQ(tolerance_class(Quantity::HelixForm, 6.5, p), 5);
  EXPECT_EQ(tolerance_class(Quantity::SinglePitch, 0.0, p), 1);
  EXPECT_EQ(tolerance_class(Quantity::SinglePitch, 1000.0, p), kWorseThanClass11);
  EXPECT_EQ(class_label(kWorseThanClass11), "worse than 11");
  EXPECT_EQ(class_label(7), "7");
}

TEST(Validity, RefusesGearsOutsideTheRange) {
  const auto refused = [](const GearParameters& p, const std::string& needle) {
    const auto why = validity_refusal(p);
    ASSERT_TRUE(why.has_value()) << "accepted; expected a refusal mentioning " << needle;
    EXPECT_NE(why->find(needle), std::string::npos) << *why;
    EXPECT_THROW(tolerance_class(Quantity::SinglePitch, 1.0, p), std::domain_error);
    EXPECT_THROW(tolerances(p, 5), std::domain_error);
  };
  refused(gear(2, 100, 20, 4), "z = 4");
  refused(gear(2, 100, 2), "b = 2 mm");
  refused(gear(2, 100, 20, 30, 50.0), "|β| = 50° exceeds 45°");
  refused(gear(2, 100, 20, 30, -50.0), "|β| = 50° exceeds 45°");
  refused(gear(0.4, 100, 20), "m_n = 0.4 mm");
  refused(gear(2, 4, 20), "d = 4 mm");
  refused(gear(2, 16000, 20), "d = 16000 mm");
  refused(gear(2, 100, 20, 1001), "z = 1001");
  // Several at once are all named.
  const auto why = validity_refusal(gear(2, 100, 2, 4, 50.0));
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("z = 4"), std::string::npos);
  EXPECT_NE(why->find("b = 2"), std::string::npos);
  EXPECT_NE(why->find("50°"), std::string::npos);
  // The limits themselves are inside.
  EXPECT_FALSE(validity_refusal(gear(0.5, 5, 4, 5, 45.0)));
  EXPECT_FALSE(validity_refusal(gear(70, 15000, 1200, 1000, -45.0)));
}
