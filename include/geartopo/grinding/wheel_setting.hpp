// geartopo — how the form wheel is set against the gear (docs/grinding.md).
//
// The wheel spins about its frame's y axis. With the chain wMg = Rz(γ)⁻¹·Tx(X)·Tz(Z)·Rx(A)·Ty(Y) the wheel axis in
// the workpiece frame is (sin γ cos A, cos γ cos A, sin A) and its common perpendicular with the gear axis lies along
// the C-rotated x axis at height Z. The wheel's mid-plane must contain the helix tangent at the reference cylinder,
// (0, sin β, cos β) at γ = 0, which gives A = −β (signed β, so a right-hand gear is ground at A = −|β|).
// The centre distance X makes the wheel's outer diameter reach the root diameter.
// Units: mm, rad.
#pragma once

#include "geartopo/gears/gear_geometry.hpp"

namespace geartopo::grinding {

struct WheelSetting {
  double outer_diameter_mm = 0.0;   ///< D_w, largest wheel diameter (its tip grinds the root)
  double centre_distance_mm = 0.0;  ///< X = (d_f + D_w) / 2
  double tilt_rad = 0.0;            ///< A = −β
  double axial_position_mm = 0.0;   ///< Y, position of the wheel centre along its axis from the common perpendicular
};

/// Throws FieldError("wheel.outer_diameter_mm") unless D_w > 4h, h = (d_a − d_f)/2 the tooth depth: a form wheel's
/// rim carries the tooth space's profile, h deep, and below it needs a body at least as deep again to hold that
/// profile on the arbor, so its radius exceeds 2h. (A 14 mm wheel for a module-14 gear, h ≈ 31 mm, would have its
/// profile pass through its own axis.)
void check_wheel_diameter(const gears::GearGeometry& g, double outer_diameter_mm);

/// check_wheel_diameter, then the setting.
WheelSetting make_wheel_setting(const gears::GearGeometry& g, double outer_diameter_mm, double axial_position_mm);

} // namespace geartopo::grinding
