// Wheel profile error on each wheel flank separately: the dresser's two flank passes (or two dressing discs) are set
// independently, so one wheel flank can carry a slope or crowning error the other does not have — and only the gear
// flanks ground by that wheel flank show it. Parameters as the gear-profile errors caused (plus material), per gear
// flank: a slope from root to tip and a crowning (middle above the ends) over the active profile, as wheel_profile.
// Diagnosis tries it one wheel flank at a time, after the library (docs/diagnosis.md, "Beyond the library").
#include "dressed_profile.hpp"

#include "geartopo/effects/effect.hpp"

#include <optional>

namespace geartopo::effects {
namespace {

class WheelFlankProfile final : public Effect {
public:
  WheelFlankProfile() { init_defaults(); }
  std::string_view type() const override { return "wheel_flank_profile"; }
  std::string_view explanation() const override {
    return "one wheel flank was dressed with a profile slope or crowning error, copied onto the gear flanks it grinds";
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> p{
        {"left_slope_um", "profile slope on the left gear flanks (tip minus root)", 0.0, -500.0, 500.0, 3.0, true, {},
         -100.0, 100.0, /*whole*/ false, /*linear*/ true},
        {"left_crowning_um", "profile crowning on the left gear flanks (middle above the ends)", 0.0, -500.0, 500.0, 3.0,
         true, {}, -100.0, 100.0, /*whole*/ false, /*linear*/ true},
        {"right_slope_um", "profile slope on the right gear flanks (tip minus root)", 0.0, -500.0, 500.0, 3.0, true, {},
         -100.0, 100.0, /*whole*/ false, /*linear*/ true},
        {"right_crowning_um", "profile crowning on the right gear flanks (middle above the ends)", 0.0, -500.0, 500.0,
         3.0, true, {}, -100.0, 100.0, /*whole*/ false, /*linear*/ true}};
    return p;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<WheelFlankProfile>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the default identity table

  void bind(const grinding::GrindingSetup& s) override {
    Effect::bind(s);
    profile_.emplace(s);
  }

  double wheel_radius_error_mm(double v, const grinding::PathPoint&) const override {
    const bool left = profile_->grinds_left(v);
    return profile_->radius_error_mm(setup(), v, value(left ? 0 : 2), value(left ? 1 : 3));
  }

private:
  std::optional<DressedProfile> profile_; ///< where the active profile lies on the wheel; set by bind
};

} // namespace

std::unique_ptr<Effect> make_wheel_flank_profile() { return std::make_unique<WheelFlankProfile>(); }

} // namespace geartopo::effects
