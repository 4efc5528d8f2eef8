// Wheel profile wear with ground length: the wheel does not wear evenly over its profile — its outer edge, which
// grinds the root of both gear flanks, and its flanks near the tip wear at their own rates — so the profile the wheel
// copies changes a little with every stroke until it is dressed. Parameters as the change of the gear-profile errors
// it causes per stroke (plus material), over the active profile: a slope from root to tip and a crowning (middle above
// the ends), both wheel flanks alike (the edge is shared). Diagnosis tries it beyond the library (docs/diagnosis.md).
#include "dressed_profile.hpp"
#include "strokes_since_dressing.hpp"

#include "geartopo/effects/effect.hpp"

#include <cmath>
#include <optional>

namespace geartopo::effects {
namespace {

class WheelProfileWear final : public Effect {
public:
  WheelProfileWear() { init_defaults(); }
  std::string_view type() const override { return "wheel_profile_wear"; }
  std::string_view explanation() const override {
    return "the wheel's profile wears unevenly with every stroke until it is dressed, so the profile slope and crowning "
           "change along the grinding order";
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> p{
        {"profile_slope_um_per_stroke", "change of the gear profile slope per stroke (tip minus root)", 0.0, -50.0,
         50.0, 0.3, true, {}, -5.0, 5.0, /*whole*/ false, /*linear*/ true},
        {"profile_crowning_um_per_stroke", "change of the gear profile crowning per stroke (middle above the ends)", 0.0,
         -50.0, 50.0, 0.3, true, {}, -5.0, 5.0, /*whole*/ false, /*linear*/ true},
        {"dressing_interval_strokes", "strokes between dressings (0: not dressed during the gear)", 0.0, 0.0, 1e5, 1.0,
         false, {}, NAN, NAN, true}};
    return p;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<WheelProfileWear>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the default identity table

  void bind(const grinding::GrindingSetup& s) override {
    Effect::bind(s);
    profile_.emplace(s);
  }

  double wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const override {
    const double strokes = strokes_since_dressing(setup(), pp, static_cast<int>(std::lround(value(2))));
    return profile_->radius_error_mm(setup(), v, value(0) * strokes, value(1) * strokes);
  }

private:
  std::optional<DressedProfile> profile_; ///< where the active profile lies on the wheel; set by bind
};

} // namespace

std::unique_ptr<Effect> make_wheel_profile_wear() { return std::make_unique<WheelProfileWear>(); }

} // namespace geartopo::effects
