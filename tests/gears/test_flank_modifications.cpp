// The drawing's design topology (gears/flank_modifications.hpp) against the definitions written here from geometry:
// crowning as the circular arc of the drawing (sagitta C over the evaluation range), reliefs from their start and end
// diameters through the roll length ξ = √(r² − r_b²) computed in the test, end reliefs over their length; and the
// checks that refuse a relief starting outside the active profile or the face width, naming both numbers.
#include "gear_fixtures.hpp"
#include "geartopo/core/field_error.hpp"
#include "geartopo/gears/evaluation_ranges.hpp"
#include "geartopo/gears/flank_modifications.hpp"
#include "geartopo/gears/gear_geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace geartopo;
using geartopo::test::paper_gear;

namespace {

/// Depth (µm, ≥ 0) below the tangent at the middle of a circular arc of sagitta c_um over the chord length l_mm, at
/// distance x_mm from the middle: R − √(R² − x²), R = (l²/4 + c²)/(2c) (in mm).
double arc_depth_um(double c_um, double l_mm, double x_mm) {
  const double c = c_um * 1e-3, r = (l_mm * l_mm / 4.0 + c * c) / (2.0 * c);
  return (r - std::sqrt(r * r - x_mm * x_mm)) * 1e3;
}

double roll_length_mm(double d_mm, double db_mm) { return 0.5 * std::sqrt(d_mm * d_mm - db_mm * db_mm); }

struct Design {
  gears::GearGeometry g{paper_gear()};
  gears::EvaluationRanges r = gears::iso1328_ranges(g);
  gears::FlankDesign design(const gears::FlankModifications& both) const { return {g, r, {both, both, {}}}; }
};

} // namespace

TEST(FlankModifications, CrowningIsTheDrawingsArcOverTheEvaluationRange) {
  const Design d;
  gears::FlankModifications m;
  m.profile_crowning_um = 4.0;
  m.helix_crowning_um = 6.0;
  const auto design = d.design(m);
  const double xi_m = 0.5 * (d.r.xi_eval_start_mm + d.r.xi_eval_end_mm), l_a = d.r.profile_evaluation_length();
  const double z_m = 0.5 * (d.r.z_eval_start_mm + d.r.z_eval_end_mm), l_b = d.r.helix_evaluation_length();
  for (auto f : {Flank::Left, Flank::Right})
    for (double frac : {-0.5, -0.3, -0.1, 0.0, 0.2, 0.5}) {
      // The arc and its parabola differ by ~c³/l² (< 1e-6 µm here).
      EXPECT_NEAR(design.profile_um(f, xi_m + frac * l_a), -arc_depth_um(4.0, l_a, frac * l_a), 1e-6);
      EXPECT_NEAR(design.helix_um(f, z_m + frac * l_b), -arc_depth_um(6.0, l_b, frac * l_b), 1e-6);
    }
  EXPECT_NEAR(design.at_um(Flank::Left, d.r.xi_eval_end_mm, d.r.z_eval_start_mm), -10.0, 1e-9); // both ends: C_α + C_β
}

TEST(FlankModifications, TipAndRootReliefRunFromTheirStartDiameterToTheActiveProfilesEnd) {
  const Design d;
  const double db = d.g.base_diameter_mm(), da = d.g.tip_diameter_mm(), dff = d.g.root_form_diameter_mm();
  gears::FlankModifications m;
  m.tip_relief_um = 8.0;
  m.tip_relief_start_diameter_mm = da - 8.0;
  m.root_relief_um = 5.0;
  m.root_relief_start_diameter_mm = dff + 6.0;
  m.root_relief_shape = gears::ReliefShape::Arc;
  const auto design = d.design(m);
  const double xi_ca = roll_length_mm(da - 8.0, db), xi_a = roll_length_mm(da, db);
  const double xi_cf = roll_length_mm(dff + 6.0, db), xi_ff = roll_length_mm(dff, db);
  EXPECT_NEAR(design.profile_um(Flank::Right, xi_a), -8.0, 1e-9);
  EXPECT_NEAR(design.profile_um(Flank::Right, xi_ca), 0.0, 1e-9);
  EXPECT_NEAR(design.profile_um(Flank::Right, 0.5 * (xi_ca + xi_a)), -4.0, 1e-9); // linear: half way, half the amount
  EXPECT_NEAR(design.profile_um(Flank::Left, xi_ff), -5.0, 1e-9);
  EXPECT_NEAR(design.profile_um(Flank::Left, 0.5 * (xi_cf + xi_ff)), -1.25, 1e-9); // arc: half way, a quarter
  EXPECT_NEAR(design.profile_um(Flank::Left, 0.5 * (xi_cf + xi_ca)), 0.0, 1e-12);   // between them: unmodified
}

TEST(FlankModifications, EndReliefAndSlopesPerFlank) {
  const Design d;
  gears::FlankModifications left, right;
  left.end_relief_um = 10.0;
  left.end_relief_length_mm = 20.0;
  right.helix_slope_um = 3.0;
  right.profile_slope_um = -2.0;
  const gears::FlankDesign design(d.g, d.r, {left, right, {}});
  const double b = paper_gear().face_width_mm;
  EXPECT_NEAR(design.helix_um(Flank::Left, 0.0), -10.0, 1e-9);
  EXPECT_NEAR(design.helix_um(Flank::Left, b - 5.0), -7.5, 1e-9);
  EXPECT_NEAR(design.helix_um(Flank::Left, 20.0), 0.0, 1e-9);
  EXPECT_NEAR(design.helix_um(Flank::Left, 0.5 * b), 0.0, 1e-12);
  EXPECT_NEAR(design.helix_um(Flank::Right, d.r.z_eval_end_mm) - design.helix_um(Flank::Right, d.r.z_eval_start_mm), 3.0, 1e-9);
  EXPECT_NEAR(design.profile_um(Flank::Right, d.r.xi_eval_end_mm) - design.profile_um(Flank::Right, d.r.xi_eval_start_mm),
              -2.0, 1e-9);
  EXPECT_EQ(design.profile_um(Flank::Left, d.r.xi_eval_end_mm), 0.0);
  EXPECT_TRUE(gears::FlankDesign().empty());
  EXPECT_EQ(gears::FlankDesign().at_um(Flank::Left, 30.0, 40.0), 0.0);
}

TEST(FlankModifications, AReliefOutsideTheActiveProfileOrFaceIsRefusedNamingBothNumbers) {
  const Design d;
  gears::FlankModifications m;
  m.tip_relief_um = 8.0;
  m.tip_relief_start_diameter_mm = d.g.tip_diameter_mm() + 1.0;
  try {
    (void)d.design(m);
    FAIL() << "a tip relief starting above d_a was taken";
  } catch (const FieldError& e) {
    EXPECT_EQ(e.field(), "gear.modifications.both.tip_relief_start_diameter_mm");
    const std::string w = e.what();
    EXPECT_NE(w.find("outside the active profile"), std::string::npos) << w;
    EXPECT_NE(w.find("d_a = 601.475"), std::string::npos) << w;
  }
  gears::FlankModifications left;
  left.end_relief_um = 5.0;
  left.end_relief_length_mm = 80.0; // b = 150 mm: more than b/2
  try {
    (void)gears::FlankDesign(d.g, d.r, {left, {}, {}});
    FAIL() << "an end relief longer than b/2 was taken";
  } catch (const FieldError& e) {
    EXPECT_EQ(e.field(), "gear.modifications.left.end_relief_length_mm");
    EXPECT_NE(std::string(e.what()).find("b/2 = 75 mm"), std::string::npos) << e.what();
  }
}

// gear.modifications.table: interpolated bilinearly in (ξ, z), so a field bilinear in (ξ, z) is reproduced exactly at
// the table's diameters for any z (linear in z between nodes); the part at the middle of L_β is the profile part
// (dressed), the rest what the motions make. A table that does not cover L_β is refused with both ranges.
TEST(FlankModifications, ATableIsBilinearAndSplitsIntoWheelAndMotions) {
  const Design d;
  const double db = d.g.base_diameter_mm();
  const auto xi_of = [&](double dy) { return roll_length_mm(dy, db); };
  const double a = 0.002, b = -0.05; // µm per mm², µm per mm
  const auto field = [&](double xi, double z) { return a * (xi - 100.0) * (z - 40.0) + b * xi; };
  gears::DesignTable t;
  t.file = "design.csv";
  for (double dy : {545.0, 560.0, 575.0, 590.0, 605.0}) t.right.diameter_mm.push_back(dy);
  for (double z : {0.0, 50.0, 100.0, 150.0}) t.right.z_mm.push_back(z);
  for (double dy : t.right.diameter_mm)
    for (double z : t.right.z_mm) t.right.value_um.push_back(field(xi_of(dy), z));
  const gears::FlankDesign design(d.g, d.r, {{}, {}, t});
  const double z_m = 0.5 * (d.r.z_eval_start_mm + d.r.z_eval_end_mm);
  for (double dy : t.right.diameter_mm)
    for (double z : {10.0, 75.0, 123.0}) {
      const double xi = xi_of(dy);
      EXPECT_NEAR(design.at_um(Flank::Right, xi, z), field(xi, z), 1e-9);
      EXPECT_NEAR(design.profile_um(Flank::Right, xi), field(xi, z_m), 1e-9);
      EXPECT_NEAR(design.motion_target_um(Flank::Right, xi, z), field(xi, z) - field(xi, z_m), 1e-9);
    }
  EXPECT_EQ(design.at_um(Flank::Left, 120.0, 75.0), 0.0); // no table for the left flank
  gears::DesignTable narrow = t;
  narrow.right.z_mm = {20.0, 50.0, 100.0, 150.0};
  try {
    (void)gears::FlankDesign(d.g, d.r, {{}, {}, narrow});
    FAIL() << "a table that does not cover L_β was taken";
  } catch (const FieldError& e) {
    EXPECT_EQ(e.field(), "gear.modifications.table");
    EXPECT_NE(std::string(e.what()).find("covers z 20.000 … 150.000 mm; the helix evaluation range L_β needs 7.500 … 142.500 mm"),
              std::string::npos)
        << e.what();
  }
}
