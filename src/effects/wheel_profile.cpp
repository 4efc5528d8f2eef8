// Wheel profile error from dressing: the dresser leaves the wheel's flanks with a slope and a crowning error. Both
// wheel flanks get the same error (the dressing path is symmetric), so every gear flank shows the same profile
// slope and crowning. Parameters are given as the gear-profile errors they cause (plus material): a slope from root
// to tip and a crowning (middle above the ends) over the active profile.
#include "dressed_profile.hpp"

#include "geartopo/effects/effect.hpp"

#include "geartopo/gears/involute_helicoid.hpp"

#include <optional>

namespace geartopo::effects {
namespace {

class WheelProfile final : public Effect {
public:
  WheelProfile() { init_defaults(); }
  std::string_view type() const override { return "wheel_profile"; }
  std::string_view explanation() const override {
    return "the dresser left a slope or crowning on the wheel's profile, copied onto every flank's profile";
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> p{
        {"profile_slope_um", "gear profile slope it causes over the active profile (tip minus root)", 0.0, -500.0, 500.0,
         3.0, true, {}, -100.0, 100.0, /*whole*/ false, /*linear*/ true},
        {"profile_crowning_um", "gear profile crowning it causes (middle above the ends)", 0.0, -500.0, 500.0, 3.0, true, {}, -100.0, 100.0, /*whole*/ false, /*linear*/ true}};
    return p;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<WheelProfile>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the default identity table

  void bind(const grinding::GrindingSetup& s) override {
    Effect::bind(s);
    profile_.emplace(s);
  }

  double wheel_radius_error_mm(double v, const grinding::PathPoint&) const override {
    return profile_->radius_error_mm(setup(), v, value(0), value(1));
  }

private:
  std::optional<DressedProfile> profile_; ///< where the active profile lies on the wheel; set by bind
};

} // namespace

std::unique_ptr<Effect> make_wheel_profile() { return std::make_unique<WheelProfile>(); }

} // namespace geartopo::effects
