// geartopo effects, private — a dressing error of the wheel's profile as the gear-profile error it causes: where on
// the wheel the active profile lies, and the radial wheel change that leaves a given slope and crowning there
// (wheel_profile, wheel_flank_profile). Units: mm inside, µm for the slope and crowning.
#pragma once

#include "geartopo/core/cubic_spline.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/grinding/grinding_setup.hpp"

#include <cmath>
#include <vector>

namespace geartopo::effects {

struct DressedProfile {
  double r_root_mm = 0.0, r_tip_mm = 0.0; ///< wheel radii touching the start and the end of the active profile
  double v_middle_mm = 0.0;               ///< the wheel's middle plane (axial coordinate)
  bool left_above_middle = true;          ///< the left gear flanks' contacts lie at v above the middle
  /// Wheel radius (mm, ascending) → where on the active profile it grinds, as the fraction of its roll length (0 at
  /// the root, 1 at the tip): the slope and crowning are then those of the gear profile along its roll length, the
  /// direction ISO 1328-1 evaluates (a map linear in the wheel radius would skew a crowning by ~12 % into a slope).
  /// Beyond the active profile it continues along its end tangents.
  CubicSpline roll_fraction_of_radius;

  explicit DressedProfile(const grinding::GrindingSetup& s) {
    const auto& r = s.ranges();
    // Tooth 1's right flank is the reference space's right flank; the wheel axis is the wheel frame's y.
    const auto contact = [&](double xi) {
      const auto fp = s.flanks().at(1, geartopo::Flank::Right, xi, s.wheel().contact_offset_mm(geartopo::Flank::Right, xi));
      return Eigen::Vector3d(s.wheel().reference_wMg().inverse() * fp.p);
    };
    const auto radius = [&](double xi) {
      const Eigen::Vector3d q = contact(xi);
      return std::hypot(q.x(), q.z());
    };
    r_root_mm = radius(r.xi_active_start_mm);
    r_tip_mm = radius(r.xi_active_end_mm);
    // The root is ground by the wheel's larger radii: sampled from the tip (smallest radius) to the root.
    constexpr int kSamples = 33;
    std::vector<double> radii, fractions;
    for (int k = kSamples - 1; k >= 0; --k) {
      const double fraction = static_cast<double>(k) / (kSamples - 1);
      radii.push_back(radius(r.xi_active_start_mm + fraction * (r.xi_active_end_mm - r.xi_active_start_mm)));
      fractions.push_back(fraction);
    }
    roll_fraction_of_radius = CubicSpline(std::move(radii), std::move(fractions), CubicSpline::Ends::NotAKnot);
    // Both wheel flanks are dressed to the same nominal form: a right flank's contact lies on one side of the middle
    // plane, every left flank's on the other.
    v_middle_mm = 0.5 * (s.wheel().v_min() + s.wheel().v_max());
    left_above_middle = !(contact(0.5 * (r.xi_active_start_mm + r.xi_active_end_mm)).y() > v_middle_mm);
  }

  /// Where on the active profile the wheel at axial coordinate v grinds: the roll-length fraction, 0 root … 1 tip.
  double roll_fraction(const grinding::GrindingSetup& s, double v_mm) const {
    return roll_fraction_of_radius.value(s.wheel().radius(v_mm));
  }

  /// True when the wheel at axial coordinate v grinds left gear flanks.
  bool grinds_left(double v_mm) const { return (v_mm > v_middle_mm) == left_above_middle; }

  /// The change of the wheel radius at v (mm; positive: bigger wheel) that leaves a gear profile slope (tip minus
  /// root) and crowning (middle above the ends) over the active profile's roll length, plus material: the dresser's
  /// error is normal to the wheel surface, as a radial change 1/normal_per_radial larger, and a bigger wheel removes
  /// material.
  double radius_error_mm(const grinding::GrindingSetup& s, double v_mm, double slope_um, double crowning_um) const {
    const double t = roll_fraction(s, v_mm) - 0.5; // −½ at the gear's root, +½ at its tip
    const double normal = -units::mm_from_um(slope_um * t + crowning_um * (1.0 - 4.0 * t * t));
    return normal / s.wheel().normal_per_radial(v_mm);
  }
};

} // namespace geartopo::effects
