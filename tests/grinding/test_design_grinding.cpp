// The drawing's profile modifications dressed into the form wheel (FormWheel from the designed tooth space) and ground
// on an ideal machine. Truths from outside the grinder: the relief and crowning written here from the gear's base
// diameter (ξ = √(r² − r_b²)); on a spur gear the dressed modification must appear exactly as designed, and on a
// helical gear too, because the contact line is fixed relative to the wheel along the screw motion (the same wheel
// section grinds a roll length at every z: no twist comes from the wheel).
#include "../gears/gear_fixtures.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/topology.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace geartopo;

namespace {

struct Modified {
  gears::GearSpec spec;
  double c_alpha_um = 4.0, c_a_um = 8.0, d_ca_mm = 0.0;
  explicit Modified(gears::GearSpec s) : spec(s) {
    d_ca_mm = spec.tip_diameter_mm - 3.0 * spec.normal_module_mm / 4.0;
    gears::FlankModifications m;
    m.profile_crowning_um = c_alpha_um;
    m.tip_relief_um = c_a_um;
    m.tip_relief_start_diameter_mm = d_ca_mm;
    spec.modifications = {m, m, {}};
  }
  /// The design at roll length ξ from the definitions (docs/modifications.md), with this gear's evaluation range.
  double expected_um(const grinding::GrindingSetup& s, double xi) const {
    const double db = s.geometry().base_diameter_mm(), r_b = 0.5 * db;
    const auto& r = s.ranges();
    const double u = (xi - 0.5 * (r.xi_eval_start_mm + r.xi_eval_end_mm)) / r.profile_evaluation_length();
    const double xi_ca = std::sqrt(0.25 * d_ca_mm * d_ca_mm - r_b * r_b);
    const double xi_a = std::sqrt(0.25 * spec.tip_diameter_mm * spec.tip_diameter_mm - r_b * r_b);
    const double relief = xi > xi_ca ? c_a_um * (xi - xi_ca) / (xi_a - xi_ca) : 0.0;
    return -4.0 * c_alpha_um * u * u - relief;
  }
};

/// Largest |raw − expected| (µm) over a 9 × 7 grid of the active profile × face on teeth 1 and z/2, both flanks, with
/// raw the material left along the bare involute's normal (the deviation from the design plus the design).
double largest_miss_um(const Modified& m, const grinding::GrindingSetup& s) {
  const grinding::IdealProcess ideal;
  const grinding::FlankDeviation dev(s.flanks(), s.wheel(), s.path(), ideal);
  const auto& r = s.ranges();
  double worst = 0.0;
  for (int tooth : {1, s.geometry().teeth() / 2})
    for (auto f : {Flank::Left, Flank::Right})
      for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 7; ++j) {
          const double xi = r.xi_active_start_mm + (r.xi_active_end_mm - r.xi_active_start_mm) * i / 8.0;
          const double z = r.z_eval_start_mm + (r.z_eval_end_mm - r.z_eval_start_mm) * j / 6.0;
          const auto t = dev.target(tooth, f, xi, z);
          const double raw_um = 1e3 * (dev.at(t, grinding::Method::Exact).deviation_mm + t.design_mm);
          worst = std::max(worst, std::abs(raw_um - m.expected_um(s, xi)));
        }
  return worst;
}

} // namespace

TEST(DesignGrinding, ADressedTipReliefAndCrowningAppearOnASpurGearAsDesigned) {
  const Modified m(test::make_spec(4.0, 30, 20.0, 0.0, 0.2, 30.0));
  const grinding::GrindingSetup s(m.spec, {300.0, 0.0}, {});
  const double miss = largest_miss_um(m, s);
  std::printf("spur miss %.6f um\n", miss);
  EXPECT_LT(miss, 0.01);
  // The same points on the bare gear's wheel miss by the whole modification: the wheel carries it.
  gears::GearSpec bare = m.spec;
  bare.modifications = {};
  const grinding::GrindingSetup plain(bare, {300.0, 0.0}, {});
  EXPECT_GT(largest_miss_um(m, plain), 0.9 * (m.c_alpha_um + m.c_a_um));
}

TEST(DesignGrinding, ADressedProfileModificationHasNoTwistOnAHelicalGear) {
  const Modified m(test::paper_gear());
  const grinding::GrindingSetup s(m.spec, {350.0, 0.0}, {});
  const double miss = largest_miss_um(m, s);
  std::printf("helical miss %.6f um\n", miss);
  EXPECT_LT(miss, 0.05);
}
