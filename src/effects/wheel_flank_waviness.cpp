// Waviness of one wheel flank's profile: a dresser that chatters, or a worn dressing disc, leaves a wave along the
// wheel's profile, copied onto the gear flanks that wheel flank grinds. Parameters as the gear-profile deviation it
// causes (plus material), per gear flank side: the wave's cosine and sine parts, a·cos(2π n t) + b·sin(2π n t) with t
// the fraction of the active profile's roll length (0 root, 1 tip), and n its cycles over the active profile (a
// set-up value: diagnosis tries a grid of them). Diagnosis tries it beyond the library, one wheel flank at a time
// (docs/diagnosis.md, "Beyond the library"; SMT MASTA lists wheel waviness per flank among a form-grinding set-up's
// inputs).
#include "dressed_profile.hpp"

#include "geartopo/effects/effect.hpp"

#include <cmath>
#include <numbers>
#include <optional>

namespace geartopo::effects {
namespace {

class WheelFlankWaviness final : public Effect {
public:
  WheelFlankWaviness() { init_defaults(); }
  std::string_view type() const override { return "wheel_flank_waviness"; }
  std::string_view explanation() const override {
    return "one wheel flank's profile is wavy (dressing chatter), copied onto the profiles of the gear flanks it grinds";
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> p{
        {"left_cos_um", "profile wave on the left gear flanks, cosine part (1 at the root)", 0.0, -100.0, 100.0, 0.5,
         true, {}, -20.0, 20.0, /*whole*/ false, /*linear*/ true},
        {"left_sin_um", "profile wave on the left gear flanks, sine part", 0.0, -100.0, 100.0, 0.5, true, {}, -20.0,
         20.0, /*whole*/ false, /*linear*/ true},
        {"right_cos_um", "profile wave on the right gear flanks, cosine part (1 at the root)", 0.0, -100.0, 100.0, 0.5,
         true, {}, -20.0, 20.0, /*whole*/ false, /*linear*/ true},
        {"right_sin_um", "profile wave on the right gear flanks, sine part", 0.0, -100.0, 100.0, 0.5, true, {}, -20.0,
         20.0, /*whole*/ false, /*linear*/ true},
        {"cycles", "waves over the active profile", 5.0, 0.5, 50.0, 1.0, false, {}, NAN, NAN}};
    return p;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<WheelFlankWaviness>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the default identity table

  void bind(const grinding::GrindingSetup& s) override {
    Effect::bind(s);
    profile_.emplace(s);
  }

  double wheel_radius_error_mm(double v, const grinding::PathPoint&) const override {
    const bool left = profile_->grinds_left(v);
    const double t = profile_->roll_fraction(setup(), v);
    const double phase = 2.0 * std::numbers::pi * value(4) * t;
    const double deviation_um = value(left ? 0 : 2) * std::cos(phase) + value(left ? 1 : 3) * std::sin(phase);
    // plus material on the gear is a smaller wheel: the normal change −deviation, as a radial change
    return -units::mm_from_um(deviation_um) / setup().wheel().normal_per_radial(v);
  }

private:
  std::optional<DressedProfile> profile_; ///< where the active profile lies on the wheel; set by bind
};

} // namespace

std::unique_ptr<Effect> make_wheel_flank_waviness() { return std::make_unique<WheelFlankWaviness>(); }

} // namespace geartopo::effects
