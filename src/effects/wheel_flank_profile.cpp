// Wheel profile error on each wheel flank separately: the dresser's two flank passes (or two dressing discs) are set
// independently, so one wheel flank can carry a slope or crowning error the other does not have — and only the gear
// flanks ground by that wheel flank show it. Parameters as the gear-profile errors caused (plus material), per gear
// flank: a slope from root to tip and a crowning (middle above the ends) over the active profile, as wheel_profile.
// Diagnosis tries it one wheel flank at a time, after the library (docs/diagnosis.md, "Beyond the library").
#include "geartopo/effects/effect.hpp"
#include "geartopo/core/units.hpp"

#include <cmath>

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

  void bind(const grinding::GrindingSetup& s) override {
    Effect::bind(s);
    const auto& r = s.ranges();
    // Wheel radii at which the wheel touches the start and the end of the active profile (both wheel flanks are
    // dressed to the same nominal form), and on which side of the wheel's middle each gear flank's contact lies.
    auto wheel_radius_at = [&](double xi) {
      const auto fp = s.flanks().at(1, geartopo::Flank::Right, xi, s.wheel().contact_offset_mm(geartopo::Flank::Right, xi));
      const Eigen::Vector3d q = s.wheel().reference_wMg().inverse() * fp.p;
      return std::hypot(q.x(), q.z());
    };
    r_root_ = wheel_radius_at(r.xi_active_start_mm);
    r_tip_ = wheel_radius_at(r.xi_active_end_mm);
    // The wheel axis is the wheel frame's y: a right flank's contact (tooth 1, the reference space's right flank, as
    // wheel_radius_at above) lies on one side of the wheel's middle plane, every left flank's on the other.
    const double xi_mid = 0.5 * (r.xi_active_start_mm + r.xi_active_end_mm);
    const auto fp = s.flanks().at(1, geartopo::Flank::Right, xi_mid, s.wheel().contact_offset_mm(geartopo::Flank::Right, xi_mid));
    const double v_right = (s.wheel().reference_wMg().inverse() * fp.p).y();
    v_middle_ = 0.5 * (s.wheel().v_min() + s.wheel().v_max());
    left_above_ = !(v_right > v_middle_);
  }

  double wheel_radius_error_mm(double v, const grinding::PathPoint&) const override {
    const bool left = (v > v_middle_) == left_above_;
    const double slope = value(left ? 0 : 2), crowning = value(left ? 1 : 3);
    const double rho = (r_root_ - setup().wheel().radius(v)) / (r_root_ - r_tip_); // 0 at the gear's root, 1 at its tip
    const double t = rho - 0.5;
    const double normal = -units::mm_from_um(slope * t + crowning * (1.0 - 4.0 * t * t)); // a bigger wheel removes material
    return normal / setup().wheel().normal_per_radial(v);
  }

private:
  double r_root_ = 0.0, r_tip_ = 0.0, v_middle_ = 0.0;
  bool left_above_ = true;
};

} // namespace

std::unique_ptr<Effect> make_wheel_flank_profile() { return std::make_unique<WheelFlankProfile>(); }

} // namespace geartopo::effects
