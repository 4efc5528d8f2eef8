// A user's program against an installed geartopo: the gear's geometry checked against ISO 21771 formulas written
// here, and a grinding simulation on an ideal machine, whose flanks must come out exact. Exit 0 when all holds.
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/topology.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

int main() {
  using namespace geartopo;
  const double deg = std::numbers::pi / 180.0;
  gears::GearSpec spec;
  spec.normal_module_mm = 3.0;
  spec.teeth = 40;
  spec.normal_pressure_angle_rad = 20.0 * deg;
  spec.helix_angle_rad = 15.0 * deg;
  spec.face_width_mm = 30.0;
  spec.tip_diameter_mm = gears::conventional_tip_diameter(spec);
  spec.root_diameter_mm = gears::conventional_root_diameter(spec);
  const gears::GearGeometry g(spec);

  // ISO 21771: d = z m_n / cos β, tan α_t = tan α_n / cos β, d_b = d cos α_t.
  const double d = 40 * 3.0 / std::cos(15.0 * deg);
  const double alpha_t = std::atan(std::tan(20.0 * deg) / std::cos(15.0 * deg));
  const double db = d * std::cos(alpha_t);
  std::printf("d = %.6f mm (expected %.6f), d_b = %.6f mm (expected %.6f)\n", g.reference_diameter_mm(), d,
              g.base_diameter_mm(), db);
  if (std::abs(g.reference_diameter_mm() - d) > 1e-9 || std::abs(g.base_diameter_mm() - db) > 1e-9) return 1;

  const grinding::GrindingSetup setup(spec, grinding::WheelSpec{}, grinding::ProcessSpec{});
  grinding::SimulationOptions options;
  options.teeth = {1};
  const auto flanks = grinding::simulate_topology(setup, grinding::IdealProcess{}, options);
  const double largest_um = grinding::largest_abs_deviation_um(flanks);
  std::printf("ideal machine: %zu flanks, largest |deviation| %.2e um\n", flanks.size(), largest_um);
  return flanks.size() == 2 && largest_um < 1e-3 ? 0 : 1;
}
