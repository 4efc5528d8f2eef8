// Wheel runout and head vibration: the wheel centre moves radially by a cos(2πft) + b sin(2πft). Along a stroke the
// contact travels at the feed rate, so the flanks get waviness of wavelength v_feed / f along the helix. With f the
// wheel's rotation frequency this is wheel runout; the exact envelope then shows how much of it survives (at high f
// every point sees the deepest cut and the waviness flattens into a uniform offset).
#include "geartopo/effects/effect.hpp"
#include "geartopo/core/units.hpp"

#include <cmath>
#include <numbers>

namespace geartopo::effects {
namespace {

class WheelRunout final : public Effect {
public:
  WheelRunout() { init_defaults(); }
  std::string_view type() const override { return "wheel_runout"; }
  std::string_view explanation() const override {
    return "the wheel runs out or its head vibrates radially, leaving waviness along the helix";
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> p{
        {"cos_um", "radial amplitude, cosine part", 0.0, -500.0, 500.0, 1.0, true, {}, -50.0, 50.0, /*whole*/ false, /*linear*/ true},
        {"sin_um", "radial amplitude, sine part", 0.0, -500.0, 500.0, 1.0, true, {}, -50.0, 50.0, /*whole*/ false, /*linear*/ true},
        // Not fitted: strokes of different teeth are ground minutes apart, so a few measured teeth alias the frequency
        // (docs/diagnosis.md). It is a set-up value: the wheel speed / 60, or a vibration measurement.
        {"frequency_hz", "frequency of the radial motion (wheel speed / 60 for runout)", 0.5, 1e-3, 1000.0, 0.2, false}};
    return p;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<WheelRunout>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the default identity table
  machine::Vector5d command_offset(const grinding::PathPoint& pp) const override {
    const double phase = 2.0 * std::numbers::pi * value(2) * pp.time_s;
    machine::Vector5d o = machine::Vector5d::Zero();
    o(0) = units::mm_from_um(value(0) * std::cos(phase) + value(1) * std::sin(phase));
    return o;
  }
};

} // namespace

std::unique_ptr<Effect> make_wheel_runout() { return std::make_unique<WheelRunout>(); }

} // namespace geartopo::effects
