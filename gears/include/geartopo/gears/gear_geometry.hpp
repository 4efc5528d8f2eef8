// geartopo — derived geometry of a cylindrical involute gear per ISO 21771 / DIN 3960.
// A GearGeometry is built once from a GearSpec, validated, and then read-only (the gear "Model").
// Units: lengths mm, angles rad. Transverse quantities carry a "t", normal ones an "n".
#pragma once

#include "geartopo/gears/gear_spec.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace geartopo::gears {

class GearGeometry {
public:
  /// Validates the spec and computes every derived quantity.
  /// Throws FieldError naming the offending field (degenerate gear, undercut, pointed tip, …).
  explicit GearGeometry(const GearSpec& spec);

  const GearSpec& spec() const { return spec_; }
  int teeth() const { return spec_.teeth; }

  double transverse_module_mm() const { return mt_; }         ///< m_t = m_n / cos β
  double transverse_pressure_angle() const { return alpha_t_; } ///< tan α_t = tan α_n / cos β
  double base_helix_angle() const { return beta_b_; }         ///< signed like β; sin β_b = sin β cos α_n
  double reference_diameter_mm() const { return d_; }          ///< d = z m_t
  double base_diameter_mm() const { return db_; }              ///< d_b = d cos α_t
  double tip_diameter_mm() const { return spec_.tip_diameter_mm; }
  double root_diameter_mm() const { return spec_.root_diameter_mm; }
  double root_form_diameter_mm() const { return dFf_; }        ///< d_Ff, start of the involute
  /// Lead p_z = π d / tan β, signed like β (positive: right hand). Infinite for spur gears.
  double lead_mm() const;
  /// Helix parameter: rotation of the transverse profile per unit axial length, 2 tan β / d (rad/mm, signed).
  double twist_rad_per_mm() const { return twist_; }
  double transverse_base_pitch_mm() const { return pbt_; }    ///< p_bt = π d_b / z
  double normal_base_pitch_mm() const { return pbt_ * std::cos(beta_b_); }
  double transverse_pitch_mm() const { return pt_; }           ///< p_t = π m_t
  double normal_tooth_thickness_mm() const { return sn_; }     ///< s_n = m_n (π/2 + 2 x tan α_n), at d
  double transverse_tooth_thickness_mm() const { return st_; } ///< s_t = s_n / cos β, at d

  /// Half the angular tooth thickness on the base circle: s_t/d + inv α_t (rad).
  double base_half_angle() const { return psi_b_; }

  /// Transverse pressure angle α_yt at diameter d_y ≥ d_b: cos α_yt = d_b / d_y.
  double transverse_pressure_angle_at(double dy_mm) const;
  /// Transverse (arc) tooth thickness at diameter d_y: s_yt = d_y (s_t/d + inv α_t − inv α_yt).
  double transverse_tooth_thickness_at(double dy_mm) const;
  /// Normal tooth thickness at d_y: s_yn = s_yt cos β_y with tan β_y = tan β · d_y / d.
  double normal_tooth_thickness_at(double dy_mm) const;

  /// Roll length ξ = √(r² − r_b²) in the transverse plane (mm), the profile coordinate of ISO 1328 charts.
  double roll_length_at(double dy_mm) const;
  double diameter_at_roll_length(double xi_mm) const;

  /// Customary number of teeth spanned for W_k: the caliper touches the flanks near d + 2 x m_n (DIN 3960).
  int span_teeth() const { return k_; }
  /// Base tangent length over k teeth with a normal tooth-thickness allowance A_sn (mm, ISO 21771 / DIN 3960):
  ///   W_k = m_n cos α_n [(k − 0.5) π + z inv α_t] + 2 x m_n sin α_n + A_sn cos α_n.
  /// The allowance term is exact for helical gears too: A_sn moves each flank by A_sn cos α_n / 2 along its normal,
  /// and W_k is the normal distance of two flanks (the caliper's common normal lies in the base tangent plane).
  double base_tangent_length_mm(int k, double thickness_allowance_mm = 0.0) const;
  /// Diameter at which the W_k caliper touches the flanks. The caliper's common normal lies in the base tangent
  /// plane, inclined by β_b to the transverse plane, so each contact is at roll length ξ = W_k cos β_b / 2.
  double span_contact_diameter_mm(int k) const;

  /// Dimension over balls M_dK (mm) with ball diameter D_M and normal tooth-thickness allowance A_sn
  /// (ISO 21771 / DIN 3960; the DIN 21773 ball formulas use z m_n cos α_n = d_b cos β_b):
  ///   s_n' = m_n (π/2 + 2 x tan α_n) + A_sn
  ///   inv α_Mt = inv α_t + D_M / (m_n z cos α_n) + s_n' / (m_n z) − π / z
  ///   d_K = d_b / cos α_Mt                          (diameter of the circle through the ball centres)
  ///   even z: M_dK = d_K + D_M;  odd z: M_dK = d_K cos(90°/z) + D_M
  /// Both balls lie in one transverse plane (for odd z, in the spaces nearest to opposite). M_rK = M_dK/2 for even z.
  /// Throws FieldError("gear.ball_diameter_mm") when the ball would drop inside the base cylinder.
  double dimension_over_balls_mm(double ball_diameter_mm, double thickness_allowance_mm = 0.0) const;
  /// d_K of the formula above.
  double ball_centre_diameter_mm(double ball_diameter_mm, double thickness_allowance_mm = 0.0) const;
  /// Diameter where the ball touches the flanks. The contact normal lies in the base tangent plane, so in the
  /// transverse projection the contact point lies D_M cos β_b / 2 nearer the base circle than the centre along the
  /// line of action: ξ_c = (d_b/2) tan α_Mt − (D_M/2) cos β_b, d_c = 2 √((d_b/2)² + ξ_c²).
  double ball_contact_diameter_mm(double ball_diameter_mm, double thickness_allowance_mm = 0.0) const;
  /// The ball that touches exactly at d + 2 x m_n (the circle of the customary span rule; the reference circle
  /// when x = 0), at zero allowance. Found by bisection: the contact diameter grows with D_M.
  double ideal_ball_diameter_mm() const;
  /// The customary ball: the ideal ball rounded to a 0.05 mm step (0.01 mm below 1 mm). For α_n = 20° this is
  /// ≈ 1.68–1.73 m_n, the range of the usual tables (1.75 m_n tandwiel.info, 1.69 m_n drgears, 1.7 mm for m = 1
  /// MESYS), but unlike a fixed factor it keeps the contact near mid-depth for any z, x and β.
  double customary_ball_diameter_mm() const;
  /// The spec's ball, or the customary one when the spec gives none.
  double ball_diameter_mm() const { return ball_; }

  /// Smallest profile shift that avoids undercut by the basic rack (DIN 3960): x_min = h_Ff*/m_n − z sin² α_t / (2 cos β).
  double minimum_profile_shift() const { return x_min_; }
  /// Tip diameter at which the tooth becomes pointed (s_at = 0).
  double pointed_tip_diameter_mm() const { return d_pointed_; }
  /// Normal tooth thickness at the tip.
  double tip_normal_thickness_mm() const { return normal_tooth_thickness_at(spec_.tip_diameter_mm); }

  /// Non-fatal findings (e.g. thin tip), one sentence each.
  const std::vector<std::string>& warnings() const { return warnings_; }

private:
  GearSpec spec_;
  double mt_, alpha_t_, beta_b_, d_, db_, dFf_, twist_, pbt_, pt_, sn_, st_, psi_b_, x_min_, d_pointed_, ball_;
  int k_;
  std::vector<std::string> warnings_;
};

} // namespace geartopo::gears
