// Shared gear specs for the gear tests. Units: mm, rad.
#pragma once

#include "geartopo/gears/gear_spec.hpp"

#include <numbers>

namespace geartopo::test {

constexpr double kDeg = std::numbers::pi / 180.0;

/// A spec with conventional tip and root diameters.
inline gears::GearSpec make_spec(double mn, int z, double alpha_n_deg, double beta_deg, double x, double b = 20.0) {
  gears::GearSpec s;
  s.normal_module_mm = mn;
  s.teeth = z;
  s.normal_pressure_angle_rad = alpha_n_deg * kDeg;
  s.helix_angle_rad = beta_deg * kDeg;
  s.profile_shift = x;
  s.face_width_mm = b;
  s.tip_diameter_mm = gears::conventional_tip_diameter(s);
  s.root_diameter_mm = gears::conventional_root_diameter(s);
  return s;
}

/// The seed paper's gear (Table 2) with the default scene's assumed b, d_a, d_f.
inline gears::GearSpec paper_gear() { return make_spec(14.0, 35, 20.0, 30.0, 0.274, 150.0); }

} // namespace geartopo::test
