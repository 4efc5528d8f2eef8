// Servo following error of the C axis: C follows its command with a time lag against Z, C(t) = C_cmd(t − T).
// Along a stroke C turns at dC/dt = −k dZ/dt (k = 2 tan β / d), so the lag is a constant angle k·v·T whose sign
// follows the stroke direction: with alternating strokes, neighbouring spaces get opposite pitch errors.
#include "geartopo/effects/effect.hpp"
#include "geartopo/core/units.hpp"

namespace geartopo::effects {
namespace {

class ServoLag final : public Effect {
public:
  ServoLag() { init_defaults(); }
  std::string_view type() const override { return "servo_lag"; }
  std::string_view explanation() const override {
    return "the C axis lags behind Z while they follow the lead, turning every flank by an angle that flips with the "
           "stroke direction";
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> p{
        {"c_lag_ms", "time lag of C behind its command, relative to Z", 0.0, -1000.0, 1000.0, 5.0, true, {}, -50.0, 50.0, /*whole*/ false, /*linear*/ true}};
    return p;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<ServoLag>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the default identity table
  machine::Vector5d command_offset(const grinding::PathPoint& pp) const override {
    const auto& path = setup().path();
    const double v = path.process().feed_mm_per_min / 60.0 * path.stroke_direction(pp.space); // dZ/dt, mm/s
    machine::Vector5d o = machine::Vector5d::Zero();
    o(4) = setup().geometry().twist_rad_per_mm() * v * units::s_from_ms(value(0)); // −T · dC/dt
    return o;
  }
};

} // namespace

std::unique_ptr<Effect> make_servo_lag() { return std::make_unique<ServoLag>(); }

} // namespace geartopo::effects
