// Pitch (f_p, F_p, F_pk) and runout (F_r) from one normal deviation per flank, with known answers built from the
// flank geometry (docs/iso1328.md "Pitch and runout"). Units: µm, rad.
#include "eval_fixtures.hpp"

#include "geartopo/evaluation/pitch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace geartopo::evaluation;
using geartopo::Flank;
using namespace geartopo::evaluation::test;

namespace {

/// δn of every flank of a gear whose body is moved rigidly by δ (µm) along the direction ω (rad) in the transverse
/// plane. A flank point's base-tangent angle is φ (docs/conventions.md: n = σ (cos β_b e_θ(φ) − sin β_b e_z)), so
///   δn = n · δ û = σ cos β_b δ (e_θ(φ) · û) = σ cos β_b δ sin(ω − φ).
/// At d_M the measuring point of tooth j lies at θ_j ± ψ_y (right +, left −; θ_j = 2π (j − 1)/z + τ, τ the helix
/// twist at mid face width) and φ = θ_P − σ α_yt.
struct FlankSet {
  std::vector<double> right, left;
};
FlankSet eccentric(const TestGear& g, double delta_um, double omega, double tau) {
  FlankSet f;
  for (int j = 1; j <= g.z; ++j) {
    const double th = 2 * kPi * (j - 1) / g.z + tau;
    const double phiR = th + g.psi_y - g.alpha_yt, phiL = th - g.psi_y + g.alpha_yt;
    f.right.push_back(+std::cos(g.beta_b) * delta_um * std::sin(omega - phiR));
    f.left.push_back(-std::cos(g.beta_b) * delta_um * std::sin(omega - phiL));
  }
  return f;
}

double conversion(const TestGear& g) { return std::cos(g.beta_b) * std::cos(g.alpha_yt); }

} // namespace

// One flank standing proud by a (µm, normal): its position moves by a/(cos β_b cos α_yt) along the measuring circle,
// so both pitches touching it change by that amount (opposite signs) and f_p = F_p = F_pk = a/(cos β_b cos α_yt).
TEST(Pitch, OneOffsetFlankGivesItsArcShift) {
  const TestGear g = scene_gear();
  const double a = 3.0;
  for (const Flank side : {Flank::Right, Flank::Left}) {
    std::vector<double> dn(g.z, 0.0);
    dn[6] = a; // tooth 7
    const auto r = evaluate_pitch(dn, side, g.pitch_geometry());
    const double e = a / (std::cos(g.beta_b) * std::cos(g.alpha_yt));
    EXPECT_DOUBLE_EQ(r.f_p_um, e);
    EXPECT_DOUBLE_EQ(r.F_p_um, e);
    EXPECT_DOUBLE_EQ(r.F_pk_um, e);
    EXPECT_EQ(r.sector_pitches, 4); // 35/8 = 4.4 → 4
    // Plus material moves a right flank +θ and a left flank −θ.
    const double sigma = side == Flank::Right ? 1.0 : -1.0;
    EXPECT_DOUBLE_EQ(r.position_um[6], sigma * e);
    EXPECT_DOUBLE_EQ(r.single_pitch_um[5], sigma * e);  // pitch 6: tooth 6 → 7
    EXPECT_DOUBLE_EQ(r.single_pitch_um[6], -sigma * e); // pitch 7: tooth 7 → 8
    EXPECT_DOUBLE_EQ(r.index_um[6], sigma * e);
    EXPECT_DOUBLE_EQ(r.index_um[7], 0.0);
  }
}

// A turn Δγ of the whole gear moves every right flank by +r_b cos β_b Δγ and every left flank by −r_b cos β_b Δγ
// (docs/conventions.md): every flank moves by the same arc, so there is no pitch deviation and no runout.
TEST(Pitch, RotationOfTheWholeGearIsNeitherPitchNorRunout) {
  const TestGear g = scene_gear();
  const double shift = 0.5 * g.db * std::cos(g.beta_b) * 2e-5; // Δγ = 20 µrad
  const std::vector<double> right(g.z, shift), left(g.z, -shift);
  const auto pr = evaluate_pitch(right, Flank::Right, g.pitch_geometry());
  const auto pl = evaluate_pitch(left, Flank::Left, g.pitch_geometry());
  EXPECT_NEAR(pr.f_p_um, 0.0, 1e-12);
  EXPECT_NEAR(pr.F_p_um, 0.0, 1e-12);
  EXPECT_NEAR(pl.F_p_um, 0.0, 1e-12);
  EXPECT_NEAR(pr.position_um[0], pl.position_um[0], 1e-12); // both sides moved by the same +θ arc
  EXPECT_NEAR(evaluate_runout(right, left, g.pitch_geometry()).F_r_um, 0.0, 1e-12);
}

// Eccentricity δ: the ball in space s (centre at θ_c,s = θ_s + π/z) moves with the body, radially by δ cos(θ_c,s − ω).
// With an even z and ω on a space centre, the spaces s and s + z/2 see +δ and −δ: F_r = 2δ.
TEST(Runout, EccentricityGivesTwiceTheEccentricity) {
  const TestGear g(36, 14.0, 20.0, 30.0, 0.274, 150.0);
  const double delta = 7.5, tau = 0.0123; // µm; rad
  for (int space = 1; space <= 3; ++space) {
    const double omega = 2 * kPi * (space - 1) / g.z + tau + kPi / g.z;
    const FlankSet f = eccentric(g, delta, omega, tau);
    const auto r = evaluate_runout(f.right, f.left, g.pitch_geometry());
    EXPECT_NEAR(r.F_r_um, 2 * delta, 1e-9 * 2 * delta);
    EXPECT_NEAR(r.radial_um[space - 1], delta, 1e-9 * delta);
    for (int s = 1; s <= g.z; ++s) {
      const double thc = 2 * kPi * (s - 1) / g.z + tau + kPi / g.z;
      EXPECT_NEAR(r.radial_um[s - 1], delta * std::cos(thc - omega), 1e-9 * delta) << "space " << s;
    }
  }
}

// The same for the scene gear (odd z, arbitrary direction): r_s = δ cos(θ_c,s − ω) for every space, so F_r is the
// range of those values (δ (1 + cos(π/z)) when ω is on a space centre).
TEST(Runout, EccentricityOfAnOddToothedGearInAnyDirection) {
  const TestGear g = scene_gear();
  const double delta = 4.0, tau = -0.2;
  for (const double omega : {0.0, 0.3, 1.234, tau + kPi / g.z}) {
    const FlankSet f = eccentric(g, delta, omega, tau);
    const auto r = evaluate_runout(f.right, f.left, g.pitch_geometry());
    double lo = 1e300, hi = -1e300;
    for (int s = 1; s <= g.z; ++s) {
      const double v = delta * std::cos(2 * kPi * (s - 1) / g.z + tau + kPi / g.z - omega);
      EXPECT_NEAR(r.radial_um[s - 1], v, 1e-9 * delta);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    EXPECT_NEAR(r.F_r_um, hi - lo, 1e-9 * delta);
  }
  const auto r = evaluate_runout(eccentric(g, delta, tau + kPi / g.z, tau).right,
                                 eccentric(g, delta, tau + kPi / g.z, tau).left, g.pitch_geometry());
  EXPECT_NEAR(r.F_r_um, delta * (1 + std::cos(kPi / g.z)), 1e-9 * delta);
}

// Why PitchGeometry carries η: the narrow-space formula −(e_L − e_R)/(2 tan α_yt) (η = 0) reads an eccentric gear's
// runout too large by sin(α_yt + η)/sin α_yt (9 % for the scene gear's geometry).
TEST(Runout, NarrowSpaceApproximationMisstatesEccentricity) {
  const TestGear g(36, 14.0, 20.0, 30.0, 0.274, 150.0);
  const double delta = 5.0, omega = kPi / g.z;
  const FlankSet f = eccentric(g, delta, omega, 0.0);
  PitchGeometry narrow = g.pitch_geometry();
  narrow.space_half_angle_rad = 0.0;
  const auto r = evaluate_runout(f.right, f.left, narrow);
  const double factor = std::sin(g.alpha_yt + g.eta) / std::sin(g.alpha_yt);
  EXPECT_GT(factor, 1.08);
  EXPECT_NEAR(r.F_r_um, 2 * delta * factor, 1e-9 * delta);
  // And with η = 0 the formula is literally −(e_L,s+1 − e_R,s)/(2 tan α_yt).
  const auto pr = evaluate_pitch(f.right, Flank::Right, narrow), pl = evaluate_pitch(f.left, Flank::Left, narrow);
  for (int s = 0; s < g.z; ++s)
    EXPECT_NEAR(r.radial_um[s], -(pl.position_um[(s + 1) % g.z] - pr.position_um[s]) / (2 * std::tan(g.alpha_yt)),
                1e-12);
}

// Plus material on both flanks of space 5 narrows it: the ball rides out by (δn_R + δn_L)/(2 cos β_b sin(α_yt + η)).
TEST(Runout, PlusMaterialInASpacePushesTheBallOut) {
  const TestGear g = scene_gear();
  const double a = 2.0;
  std::vector<double> right(g.z, 0.0), left(g.z, 0.0);
  right[4] = a; // right flank of tooth 5
  left[5] = a;  // left flank of tooth 6
  const auto r = evaluate_runout(right, left, g.pitch_geometry());
  const double expected = 2 * a / (2 * std::cos(g.beta_b) * std::sin(g.alpha_yt + g.eta));
  EXPECT_DOUBLE_EQ(r.radial_um[4], expected);
  EXPECT_GT(r.radial_um[4], 0.0);
  EXPECT_DOUBLE_EQ(r.F_r_um, expected);
  EXPECT_EQ(std::count(r.radial_um.begin(), r.radial_um.end(), 0.0), g.z - 1);
}

// Positions e_j = j·c (a ramp with one big wrap-around pitch): f_p = (z − 1)c, F_p = (z − 1)c,
// F_pk = max(k, z − k)·c.
TEST(Pitch, SectorPitchOfARamp) {
  const TestGear g = scene_gear();
  const int z = 10;
  std::vector<double> dn;
  for (int j = 1; j <= z; ++j) dn.push_back(j * conversion(g)); // e_j = j µm on right flanks
  for (int k = 1; k < z; ++k) {
    const auto r = evaluate_pitch(dn, Flank::Right, g.pitch_geometry(), k);
    EXPECT_NEAR(r.F_pk_um, std::max(k, z - k), 1e-12) << "k = " << k;
    EXPECT_NEAR(r.f_p_um, z - 1, 1e-12);
    EXPECT_NEAR(r.F_p_um, z - 1, 1e-12);
  }
}

// k = z/8 rounded half up, at least 2, at most z − 1.
TEST(Pitch, DefaultSectorPitches) {
  EXPECT_EQ(default_sector_pitches(35), 4);  // 4.375
  EXPECT_EQ(default_sector_pitches(36), 5);  // 4.5 → 5
  EXPECT_EQ(default_sector_pitches(100), 13); // 12.5 → 13
  EXPECT_EQ(default_sector_pitches(12), 2);  // 1.5 → 2
  EXPECT_EQ(default_sector_pitches(11), 2);  // 1.375 → 1 → at least 2
  EXPECT_EQ(default_sector_pitches(5), 2);
  EXPECT_EQ(default_sector_pitches(3), 2);
  EXPECT_THROW(default_sector_pitches(2), std::invalid_argument);
}

TEST(Pitch, RefusesBadInput) {
  const TestGear g = scene_gear();
  const PitchGeometry pg = g.pitch_geometry();
  std::vector<double> dn(g.z, 0.0);
  EXPECT_THROW(evaluate_pitch(std::vector<double>{1.0, 2.0}, Flank::Right, pg), std::invalid_argument);
  EXPECT_THROW(evaluate_pitch(dn, Flank::Right, pg, g.z), std::invalid_argument);
  EXPECT_THROW(evaluate_pitch(dn, Flank::Right, pg, -1), std::invalid_argument);
  PitchGeometry bad = pg;
  bad.transverse_pressure_angle_rad = 0.0;
  EXPECT_THROW(evaluate_pitch(dn, Flank::Right, bad), std::invalid_argument);
  bad = pg;
  bad.space_half_angle_rad = -0.1;
  EXPECT_THROW(evaluate_runout(dn, dn, bad), std::invalid_argument);
  dn[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(evaluate_pitch(dn, Flank::Left, pg), std::invalid_argument);
  EXPECT_THROW(evaluate_runout(std::vector<double>(5, 0.0), std::vector<double>(6, 0.0), pg), std::invalid_argument);
}
