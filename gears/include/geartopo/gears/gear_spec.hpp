// geartopo — what a user specifies of a cylindrical involute gear (ISO 21771 / DIN 3960 symbols).
// Units: lengths mm, angles rad. The helix angle is signed: positive = right hand, negative = left hand,
// zero = spur (ISO 21771 sign rule).
#pragma once

#include "geartopo/core/flank.hpp"
#include "geartopo/gears/flank_modifications.hpp"

#include <optional>
#include <string>

namespace geartopo::gears {

enum class Hand { Right, Left, Spur };

struct GearSpec {
  double normal_module_mm = 0.0;          ///< m_n
  int teeth = 0;                          ///< z (external gear)
  double normal_pressure_angle_rad = 0.0; ///< α_n
  double helix_angle_rad = 0.0;           ///< β at the reference cylinder, signed by hand
  double profile_shift = 0.0;             ///< x (profile shift coefficient, dimensionless)
  double face_width_mm = 0.0;             ///< b
  double tip_diameter_mm = 0.0;           ///< d_a
  double root_diameter_mm = 0.0;          ///< d_f
  /// Basic rack of the cutting/grinding tool, relative to m_n (ISO 53 profile A: h_fP* = 1.25, ρ_fP* = 0.38).
  /// They fix the root form diameter d_Ff where the involute starts, unless it is given.
  double rack_dedendum_coef = 1.25;
  double rack_root_radius_coef = 0.38;
  std::optional<double> root_form_diameter_mm; ///< d_Ff; computed from the basic rack when absent
  /// Normal tooth-thickness allowances at the reference cylinder (ISO 21771 / DIN 3967: A_sne upper, A_sni lower),
  /// mm, usually ≤ 0 (less material than nominal, for backlash). Upper ≥ lower. The gear is made to s_n + A_sn with
  /// A_sni ≤ A_sn ≤ A_sne.
  double thickness_allowance_upper_mm = 0.0;
  double thickness_allowance_lower_mm = 0.0;
  /// Measuring-ball diameter D_M for the dimension over balls; absent: GearGeometry::customary_ball_diameter_mm().
  std::optional<double> ball_diameter_mm;
  /// The drawing's flank modifications (flank_modifications.hpp); none: the bare involute helicoid.
  DesignModifications modifications;

  Hand hand() const { return helix_angle_rad > 0 ? Hand::Right : helix_angle_rad < 0 ? Hand::Left : Hand::Spur; }
};

/// Conventional tip and root diameters for a shifted gear without tip shortening:
/// d_a = d + 2 m_n (1 + x), d_f = d − 2 m_n (1.25 − x).
double conventional_tip_diameter(const GearSpec& spec);
double conventional_root_diameter(const GearSpec& spec);

const char* to_string(Hand hand);
using geartopo::to_string; // Flank (core/flank.hpp)

} // namespace geartopo::gears
