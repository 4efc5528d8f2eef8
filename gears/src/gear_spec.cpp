#include "geartopo/gears/gear_spec.hpp"

#include <cmath>

namespace geartopo::gears {

double conventional_tip_diameter(const GearSpec& s) {
  const double d = s.teeth * s.normal_module_mm / std::cos(s.helix_angle_rad);
  return d + 2.0 * s.normal_module_mm * (1.0 + s.profile_shift);
}

double conventional_root_diameter(const GearSpec& s) {
  const double d = s.teeth * s.normal_module_mm / std::cos(s.helix_angle_rad);
  return d - 2.0 * s.normal_module_mm * (1.25 - s.profile_shift);
}

const char* to_string(Hand hand) {
  switch (hand) {
  case Hand::Right: return "right";
  case Hand::Left: return "left";
  case Hand::Spur: return "spur";
  }
  return "?";
}

} // namespace geartopo::gears
