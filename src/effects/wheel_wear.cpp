// Wheel wear with ground length: the wheel wears as it grinds, evenly along its surface normal over the profile, a
// little with every stroke; dressing restores it every N strokes. A smaller wheel cuts less: plus material, growing along the grinding
// order in a saw-tooth that dressing resets.
#include "geartopo/effects/effect.hpp"
#include "geartopo/core/units.hpp"

#include <algorithm>
#include <cmath>

namespace geartopo::effects {
namespace {

class WheelWear final : public Effect {
public:
  WheelWear() { init_defaults(); }
  std::string_view type() const override { return "wheel_wear"; }
  std::string_view explanation() const override {
    return "the wheel wears with every stroke until it is dressed, so teeth ground later are left thicker";
  }
  const std::vector<ParameterSpec>& parameters() const override {
    static const std::vector<ParameterSpec> p{
        {"wear_um_per_stroke", "wear (normal to the wheel surface) per stroke (one tooth space)", 0.0, -50.0, 50.0, 0.3, true, {}, -5.0, 5.0, /*whole*/ false, /*linear*/ true},
        {"dressing_interval_strokes", "strokes between dressings (0: not dressed during the gear)", 0.0, 0.0, 1e5, 1.0,
         false, {}, NAN, NAN, true}};
    return p;
  }
  std::unique_ptr<Effect> clone() const override { return std::make_unique<WheelWear>(*this); }
  bool table_in_gear_is_constant() const override { return true; } // the default identity table
  double wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const override {
    const auto& path = setup().path();
    double strokes = path.stroke_index(pp.space);
    const int interval = static_cast<int>(std::lround(value(1)));
    if (interval > 0) strokes = std::fmod(strokes, interval);
    const double progress = std::clamp(path.stroke_progress(pp.space, pp.z_stroke_mm), 0.0, 1.0);
    const double normal_wear = units::mm_from_um(value(0)) * (strokes + progress);
    return -normal_wear / setup().wheel().normal_per_radial(v); // normal wear as a radial change
  }
};

} // namespace

std::unique_ptr<Effect> make_wheel_wear() { return std::make_unique<WheelWear>(); }

} // namespace geartopo::effects
