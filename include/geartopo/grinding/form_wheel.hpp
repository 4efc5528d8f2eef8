// geartopo — the form wheel: a surface of revolution synthesized from the gear's tooth space (docs/grinding.md).
//
// Wheel frame g: origin at the wheel centre, y = spin axis. A wheel point at axial coordinate v = y_g and radius
// ρ = √(x_g² + z_g²) is on the wheel surface when ρ = R(v).
//
// Synthesis (profile grinding's contact condition): with the wheel at its nominal pose in space 1 at Z = 0, a point
// P of a flank is a contact point when the flank normal at P meets the wheel axis, (P − O)·(n × u) = 0 (O wheel
// centre, u wheel axis). For each roll length ξ this fixes the contact point's axial position z_c(ξ) on each of the
// two flanks of the space; turning these contact lines about the wheel axis gives R(v). The screw motion of the path
// keeps the contact line fixed relative to the wheel, so the same wheel grinds every space and every z.
// Below the root form diameter the wheel tip is a smooth blend that reaches the root diameter.
// Designed profile modifications (crowning, slope, tip and root relief) are dressed into the wheel: the synthesis runs
// on the designed flank P + m(ξ) n instead of P, so the same wheel grinds them on every space and z.
// Units: mm.
#pragma once

#include "geartopo/core/flank.hpp"
#include "geartopo/gears/flank_modifications.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/grinding/wheel_setting.hpp"
#include "geartopo/core/cubic_spline.hpp"
#include "geartopo/machine/twist.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace geartopo::grinding {

class FormWheel {
public:
  /// `design`: the drawing's modifications; the wheel is dressed with their profile part (the dresser is programmed
  /// from the designed tooth space: contact points on the flank moved by m(ξ) along the normal, contact condition on
  /// that surface). Empty: the bare involute.
  FormWheel(const gears::GearGeometry& g, const WheelSetting& setting, gears::FlankDesign design = {});

  /// R(v): wheel radius at axial coordinate v; −∞ outside the wheel's width (no material there).
  double radius(double v) const {
    if (v < v_min_ || v > v_max_) return -std::numeric_limits<double>::infinity();
    return profile_.value(v);
  }
  /// dR/dv inside the width.
  double slope(double v) const { return profile_.derivative(v); }
  /// {radius(v), slope(v)} with one search in the profile (the same bits), and where v lies in it (for
  /// second_derivative_bound).
  struct ProfilePoint {
    double radius = 0.0; ///< −∞ outside the wheel's width
    double slope = 0.0;
    geartopo::CubicSpline::Location where;
  };
  ProfilePoint profile_at(double v) const {
    const auto l = profile_.locate(v);
    if (v < v_min_ || v > v_max_) return {-std::numeric_limits<double>::infinity(), profile_.derivative(v), l};
    const auto [r, s] = profile_.value_and_derivative_at(l);
    return {r, s, l};
  }
  /// An upper bound of |R″| within `reach` of the profile point's v (mm⁻¹; CubicSpline::second_derivative_bound).
  double second_derivative_bound(const ProfilePoint& p, double reach) const {
    return profile_.second_derivative_bound(p.where, reach);
  }
  /// How far the surface moves along its normal when the radius grows by one unit at v: 1/√(1 + R′(v)²). A radial
  /// change δR of the wheel moves its surface by δR/√(1 + R′²) along the normal — much less on the steep flanks.
  double normal_per_radial(double v) const {
    const double s = profile_.derivative(v);
    return 1.0 / std::sqrt(1.0 + s * s);
  }
  double v_min() const { return v_min_; }
  double v_max() const { return v_max_; }

  /// Axial offset z_c − Z of the contact point at roll length ξ on the flank of type `flank` (right flank of the tooth
  /// before the space, left flank of the tooth after it), relative to the stroke position Z.
  double contact_offset_mm(geartopo::Flank flank, double roll_length_mm) const;
  /// Range of contact offsets over the synthesized roll lengths: the stroke must run beyond the face by these.
  double min_contact_offset_mm() const { return z_c_min_; }
  double max_contact_offset_mm() const { return z_c_max_; }

  /// The axial profile (v, R) as synthesized, ordered by v, for reports and plots.
  const std::vector<double>& profile_v() const { return v_; }
  const std::vector<double>& profile_r() const { return r_; }

  /// Nominal wheel pose of the synthesis (space 1, Z = 0).  wMg
  const machine::Pose& reference_wMg() const { return wMg_ref_; }
  /// The design the wheel was dressed from: its profile part is in R(v); deviations are taken against all of it.
  const gears::FlankDesign& design() const { return design_; }

private:
  gears::FlankDesign design_;
  geartopo::CubicSpline profile_;
  geartopo::CubicSpline contact_right_, contact_left_; // z_c(ξ) per flank type
  std::vector<double> v_, r_;
  double v_min_ = 0.0, v_max_ = 0.0, z_c_min_ = 0.0, z_c_max_ = 0.0;
  machine::Pose wMg_ref_;
};

} // namespace geartopo::grinding
