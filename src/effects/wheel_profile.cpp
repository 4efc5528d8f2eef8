// Wheel profile error from dressing: the dresser leaves the wheel's flanks with a slope and a crowning error. Both
// wheel flanks get the same error (the dressing path is symmetric), so every gear flank shows the same profile
// slope and crowning. Parameters are given as the gear-profile errors they cause (plus material): a slope from root
// to tip and a crowning (middle above the ends) over the active profile.
#include "geartopo/effects/effect.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/gears/involute_helicoid.hpp"

#include <cmath>

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

  void bind(const grinding::GrindingSetup& s) override {
    Effect::bind(s);
    // Wheel radii at which the wheel touches the start and the end of the active profile.
    const auto& r = s.ranges();
    auto wheel_radius_at = [&](double xi) {
      const auto fp = s.flanks().at(1, geartopo::Flank::Right, xi, s.wheel().contact_offset_mm(geartopo::Flank::Right, xi));
      const Eigen::Vector3d q = s.wheel().reference_wMg().inverse() * fp.p;
      return std::hypot(q.x(), q.z());
    };
    r_root_ = wheel_radius_at(r.xi_active_start_mm);
    r_tip_ = wheel_radius_at(r.xi_active_end_mm);
  }

  double wheel_radius_error_mm(double v, const grinding::PathPoint&) const override {
    const double rho = (r_root_ - setup().wheel().radius(v)) / (r_root_ - r_tip_); // 0 at the gear's root, 1 at its tip
    const double t = rho - 0.5;
    // The dresser's error is normal to the wheel surface; as a radial change it is 1/normal_per_radial larger.
    const double normal = -units::mm_from_um(value(0) * t + value(1) * (1.0 - 4.0 * t * t)); // a bigger wheel removes material
    return normal / setup().wheel().normal_per_radial(v);
  }

private:
  double r_root_ = 0.0, r_tip_ = 0.0;
};

} // namespace

std::unique_ptr<Effect> make_wheel_profile() { return std::make_unique<WheelProfile>(); }

} // namespace geartopo::effects
