// Whole-gear evaluation: mean slopes, availability of pitch and runout, classification and its refusal
// (docs/iso1328.md). Units: mm, µm, rad.
#include "eval_fixtures.hpp"

#include "geartopo/evaluation/gear_evaluation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

using namespace geartopo::evaluation;
using geartopo::Flank;
using namespace geartopo::evaluation::test;

namespace {

/// Linear trace with rise `rise_um` across [start, end].
Trace ramp(double start, double end, double rise_um) {
  return sampled([=](double x) { return rise_um * (x - start) / (end - start); }, start, end, 31, 2);
}

/// All 2z flanks of the scene gear: profile rise f_Hα = 1 + 0.1·tooth (right) or −0.5 (left), helix rise 2 (right)
/// or tooth·0.2 (left); plus one pitch point per flank, tooth 7 right standing proud by 1 µm.
GearMeasurement full_gear(const TestGear& g) {
  GearMeasurement m;
  for (int t = 1; t <= g.z; ++t)
    for (const Flank s : {Flank::Left, Flank::Right}) {
      FlankMeasurement f;
      f.tooth = t;
      f.side = s;
      f.profile = ramp(kProfileStart, kProfileEnd, s == Flank::Right ? 1.0 + 0.1 * t : -0.5);
      f.helix = ramp(kHelixStart, kHelixEnd, s == Flank::Right ? 2.0 : 0.2 * t);
      m.flanks.push_back(f);
      m.pitch_points.push_back({t, s, (t == 7 && s == Flank::Right) ? 1.0 : 0.0});
    }
  m.pitch_geometry = g.pitch_geometry();
  // These tests are about means, availability and classes: the values as given (normal, rise towards +z). The
  // direction and the sign rules have their own tests (test_iso_conventions.cpp).
  m.conventions = {IsoDirection::Normal, HelixSlopeSign::RiseTowardsPlusZ, g.beta_b};
  return m;
}

const QuantityClass& find(const Classification& c, Quantity q) {
  const auto it = std::find_if(c.quantities.begin(), c.quantities.end(),
                               [&](const QuantityClass& e) { return e.quantity == q; });
  if (it == c.quantities.end()) throw std::runtime_error("quantity not classified");
  return *it;
}

} // namespace

TEST(GearEvaluation, MeanSlopesPerSide) {
  const TestGear g = scene_gear();
  const auto r = evaluate_gear(full_gear(g), g.parameters());
  ASSERT_EQ(r.flanks.size(), 70u);
  EXPECT_EQ(r.right.flanks, 35);
  EXPECT_EQ(r.left.flanks, 35);
  EXPECT_NEAR(*r.right.f_Halpha_m_um, 1.0 + 0.1 * 18, 1e-9); // mean tooth number 18
  EXPECT_NEAR(*r.left.f_Halpha_m_um, -0.5, 1e-9);
  EXPECT_NEAR(*r.right.f_Hbeta_m_um, 2.0, 1e-9);
  EXPECT_NEAR(*r.left.f_Hbeta_m_um, 0.2 * 18, 1e-9);
}

TEST(GearEvaluation, AllTeethGivePitchAndRunout) {
  const TestGear g = scene_gear();
  const auto r = evaluate_gear(full_gear(g), g.parameters());
  ASSERT_TRUE(r.pitch_right && r.pitch_left && r.runout);
  const double e = 1.0 / (std::cos(g.beta_b) * std::cos(g.alpha_yt));
  EXPECT_DOUBLE_EQ(r.pitch_right->f_p_um, e);
  EXPECT_DOUBLE_EQ(r.pitch_right->F_p_um, e);
  EXPECT_DOUBLE_EQ(r.pitch_left->F_p_um, 0.0);
  EXPECT_DOUBLE_EQ(r.runout->F_r_um, 1.0 / (2 * std::cos(g.beta_b) * std::sin(g.alpha_yt + g.eta)));
  EXPECT_TRUE(r.notes.empty());
}

TEST(GearEvaluation, SubsetOfTeethGivesNoPitchOrRunout) {
  const TestGear g = scene_gear();
  GearMeasurement m = full_gear(g);
  // Drop the pitch point of tooth 20 left; keep only flanks of teeth 1, 10, 19, 28 (the ISO four-teeth practice).
  m.pitch_points.erase(std::remove_if(m.pitch_points.begin(), m.pitch_points.end(),
                                      [](const PitchPoint& p) { return p.tooth == 20 && p.side == Flank::Left; }),
                       m.pitch_points.end());
  m.flanks.erase(std::remove_if(m.flanks.begin(), m.flanks.end(),
                                [](const FlankMeasurement& f) { return (f.tooth - 1) % 9 != 0; }),
                 m.flanks.end());
  const auto r = evaluate_gear(m, g.parameters());
  EXPECT_EQ(r.flanks.size(), 8u);
  EXPECT_TRUE(r.pitch_right.has_value());
  EXPECT_FALSE(r.pitch_left.has_value());
  EXPECT_FALSE(r.runout.has_value());
  ASSERT_EQ(r.notes.size(), 2u);
  EXPECT_NE(r.notes[0].find("left flanks not available: 34 of 35"), std::string::npos) << r.notes[0];
  EXPECT_NE(r.notes[1].find("runout not available"), std::string::npos) << r.notes[1];
  EXPECT_THROW(find(r.classification, Quantity::Runout), std::runtime_error);
  EXPECT_NEAR(*r.right.f_Halpha_m_um, 1.0 + 0.1 * (1 + 10 + 19 + 28) / 4.0, 1e-9);

  // No pitch points at all: nothing about pitch, no pitch geometry needed.
  m.pitch_points.clear();
  m.pitch_geometry.reset();
  const auto r2 = evaluate_gear(m, g.parameters());
  EXPECT_FALSE(r2.pitch_right || r2.pitch_left || r2.runout);
}

// The overall class is the worst quantity. Scene gear class limits (rounded, by hand from the formulas):
// f_HαT: A4 7.0, A5 10, A6 14 (10.1658·√2 = 14.38) → a slope of −12 µm is class 6 (compared by absolute value);
// F_αT: A4 12 (16.2676/√2 = 11.50) → F_α = 12 is class 4. Everything else is small.
TEST(GearEvaluation, OverallClassIsTheWorstQuantity) {
  const TestGear g = scene_gear();
  GearMeasurement m = full_gear(g);
  for (auto& f : m.flanks) {
    f.profile = ramp(kProfileStart, kProfileEnd, (f.tooth == 3 && f.side == Flank::Left) ? -12.0 : 0.5);
    f.helix = ramp(kHelixStart, kHelixEnd, 0.3);
  }
  const auto r = evaluate_gear(m, g.parameters());
  const Classification& c = r.classification;
  ASSERT_FALSE(c.refusal);
  const auto& slope = find(c, Quantity::ProfileSlope);
  EXPECT_NEAR(slope.worst_value_um, -12.0, 1e-9);
  EXPECT_EQ(slope.where, "tooth 3 left");
  EXPECT_EQ(slope.flank_class, 6);
  EXPECT_EQ(find(c, Quantity::ProfileTotal).flank_class, 4);
  EXPECT_EQ(find(c, Quantity::ProfileForm).flank_class, 1);
  EXPECT_EQ(find(c, Quantity::SinglePitch).where, "right flanks");
  EXPECT_EQ(c.quantities.size(), 9u);
  for (const auto& q : c.quantities) EXPECT_LE(*q.flank_class, 6) << symbol(q.quantity);
  EXPECT_EQ(c.overall, 6);
  EXPECT_EQ(c.governing, Quantity::ProfileSlope);

  // One flank far beyond class 11 makes the gear "worse than 11".
  m.flanks[0].helix = ramp(kHelixStart, kHelixEnd, 500.0);
  const auto worse = evaluate_gear(m, g.parameters());
  EXPECT_EQ(worse.classification.overall, kWorseThanClass11);
  // F_β and f_Hβ are both 500 µm; on a tie the first listed (F_β) governs.
  EXPECT_EQ(worse.classification.governing, Quantity::HelixTotal);
}

// Outside the range of validity the deviations are still computed, but no class is given.
TEST(GearEvaluation, ClassificationRefusedOutsideTheRangeOfValidity) {
  const TestGear g = scene_gear();
  GearParameters p = g.parameters();
  p.helix_angle_rad = deg(50.0);
  const auto r = evaluate_gear(full_gear(g), p);
  ASSERT_TRUE(r.classification.refusal);
  EXPECT_NE(r.classification.refusal->find("50"), std::string::npos);
  EXPECT_FALSE(r.classification.overall);
  EXPECT_EQ(r.flanks.size(), 70u);
  EXPECT_TRUE(r.pitch_right && r.runout);
  EXPECT_FALSE(r.classification.quantities.empty());
  for (const auto& q : r.classification.quantities) EXPECT_FALSE(q.flank_class) << symbol(q.quantity);

  p = g.parameters();
  p.teeth = 4; // only teeth 1..4 are then valid
  GearMeasurement m;
  for (int t = 1; t <= 4; ++t)
    for (const Flank s : {Flank::Left, Flank::Right}) {
      m.flanks.push_back({t, s, ramp(kProfileStart, kProfileEnd, 1.0), ramp(kHelixStart, kHelixEnd, 1.0)});
      m.pitch_points.push_back({t, s, 0.1 * t});
    }
  m.pitch_geometry = g.pitch_geometry();
  const auto r4 = evaluate_gear(m, p);
  ASSERT_TRUE(r4.classification.refusal);
  EXPECT_NE(r4.classification.refusal->find("z = 4"), std::string::npos);
  EXPECT_TRUE(r4.pitch_left && r4.runout);

  p = g.parameters();
  p.face_width_mm = 2.0;
  EXPECT_NE(evaluate_gear(full_gear(g), p).classification.refusal->find("b = 2"), std::string::npos);
}

TEST(GearEvaluation, RefusesInconsistentInput) {
  const TestGear g = scene_gear();
  GearMeasurement m = full_gear(g);
  m.flanks.push_back(m.flanks[5]);
  EXPECT_THROW(evaluate_gear(m, g.parameters()), std::invalid_argument);
  m = full_gear(g);
  m.flanks[0].tooth = 36;
  EXPECT_THROW(evaluate_gear(m, g.parameters()), std::invalid_argument);
  m = full_gear(g);
  m.pitch_points.push_back({1, Flank::Left, 0.0});
  EXPECT_THROW(evaluate_gear(m, g.parameters()), std::invalid_argument);
  m = full_gear(g);
  m.pitch_geometry.reset();
  EXPECT_THROW(evaluate_gear(m, g.parameters()), std::invalid_argument);
}
