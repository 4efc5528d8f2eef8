// Workpiece eccentricity and wobble on the C axis: the gear's axis is not the C axis. Its axis is displaced by
// (e_x, e_y) in the gear frame and tilted by (w_x, w_y) about the gear's x and y axes, pivoting at mid face width.
// Eccentricity gives runout and a once-per-turn pitch error; wobble a once-per-turn helix slope.
#include "geartopo/effects/effect.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/machine/transforms.hpp"

namespace geartopo::effects {
namespace {

class Eccentricity final : public Effect {
public:
  Eccentricity() { init_defaults(); }
  std::string_view type() const override { return "eccentricity"; }
  std::string_view explanation() const override {
    return "the gear is clamped off the C axis (eccentric or tilted), so pitch, runout and helix slope vary once per "
           "turn";
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> p{
        {"ecc_x_um", "gear axis offset from the C axis along the gear's x", 0.0, -1000.0, 1000.0, 5.0, true, {}, -100.0, 100.0},
        {"ecc_y_um", "gear axis offset from the C axis along the gear's y", 0.0, -1000.0, 1000.0, 5.0, true, {}, -100.0, 100.0},
        {"wobble_x_urad", "tilt of the gear axis about the gear's x (pivot at mid face)", 0.0, -5000.0, 5000.0, 20.0, true, {}, -1000.0, 1000.0},
        {"wobble_y_urad", "tilt of the gear axis about the gear's y (pivot at mid face)", 0.0, -5000.0, 5000.0, 20.0, true, {}, -1000.0, 1000.0}};
    return p;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<Eccentricity>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the clamping does not move along the path
  machine::Pose table_in_gear(const grinding::PathPoint&) const override {
    const double half = 0.5 * setup().geometry().spec().face_width_mm;
    // Pose of the gear in the table frame; the table (where the machine's poses live) in the gear frame is its inverse.
    const machine::Pose cMw = machine::translation(units::mm_from_um(value(0)), units::mm_from_um(value(1)), 0.0) * machine::translation(0, 0, half) *
                              machine::Rx(units::rad_from_urad(value(2))) * machine::Ry(units::rad_from_urad(value(3))) * machine::translation(0, 0, -half);
    return cMw.inverse();
  }
};

} // namespace

std::unique_ptr<Effect> make_eccentricity() { return std::make_unique<Eccentricity>(); }

} // namespace geartopo::effects
