#include "geartopo/grinding/wheel_setting.hpp"

#include "geartopo/core/field_error.hpp"

#include <fmt/format.h>

namespace geartopo::grinding {

void check_wheel_diameter(const gears::GearGeometry& g, double outer_diameter_mm) {
  const double depth = 0.5 * (g.tip_diameter_mm() - g.root_diameter_mm());
  if (!(outer_diameter_mm > 4.0 * depth))
    throw FieldError("wheel.outer_diameter_mm",
                     fmt::format("{} mm is too small for this gear: the wheel's rim carries the tooth space's profile, "
                                 "h = {:.3f} mm deep (the tooth depth), and needs a body at least as deep below it to "
                                 "hold it, so its diameter must exceed 4h = {:.3f} mm",
                                 outer_diameter_mm, depth, 4.0 * depth));
}

WheelSetting make_wheel_setting(const gears::GearGeometry& g, double outer_diameter_mm, double axial_position_mm) {
  check_wheel_diameter(g, outer_diameter_mm);
  WheelSetting s;
  s.outer_diameter_mm = outer_diameter_mm;
  s.centre_distance_mm = 0.5 * (g.root_diameter_mm() + outer_diameter_mm);
  s.tilt_rad = -g.spec().helix_angle_rad;
  s.axial_position_mm = axial_position_mm;
  return s;
}

} // namespace geartopo::grinding
