// The Monte Carlo draw of a table's standard-uncertainty column (docs/monte-carlo.md, "The model"): a column holding
// the constant u0 gives the draws of the scene's per-component u0 (the documented equivalence: both are value + z·u0
// with the same z), and differs from the scene's default of its kind, which the column replaces.
// Units: µm in the table files and the gear quantities.
#include "geartopo/compensation/compensator.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/scene/scene.hpp"
#include "small_gear_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

using namespace geartopo;

namespace {

// A small helical gear, one X table (delta_xx over the whole X stroke), the scene's default uncertainties otherwise.
workbench::Workbench table_uncertainty_workbench(const std::filesystem::path& dir, const std::string& table_text,
                                                 const std::string& machine_extra) {
  std::ofstream(dir / "x.csv") << table_text;
  const auto scene_file = dir / "scene.yaml";
  std::ofstream(scene_file) << test::small_gear_scene_text("  tables: [x.csv]\n" + machine_extra);
  return workbench::Workbench(scene::load_scene(scene_file));
}

const std::string kTableValues = "x_mm,delta_xx_um\n0,0\n300,3\n600,4\n900,9\n";
const std::string kTableWithConstantU = "x_mm,delta_xx_um,u_delta_xx_um\n0,0,0.7\n300,3,0.7\n600,4,0.7\n900,9,0.7\n";

} // namespace

TEST(MonteCarloTableUncertainty, AConstantColumnDrawsLikeTheComponentsOverride) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_mc_u_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto column = table_uncertainty_workbench(dir, kTableWithConstantU, "");
  const auto override_u = table_uncertainty_workbench(dir, kTableValues, "  uncertainty: {components: {delta_xx_um: 0.7}}\n");
  const auto kind_default = table_uncertainty_workbench(dir, kTableValues, ""); // linear_axis_um: 1 µm
  std::filesystem::remove_all(dir);

  compensation::CompensationOptions co;
  co.step_mm = 2.0;
  // The nominal maps are the same in the three scenes: one correction table for all.
  const auto table = compensation::compute_corrections(column.setup, column.process(),
                                                       {column.machine, column.scene.machine.datum_face_z_mm}, co);
  pipeline::MonteCarloOptions o;
  o.samples = 2;
  o.seed = 11;
  const auto a = pipeline::run_monte_carlo(column, table, o);
  const auto b = pipeline::run_monte_carlo(override_u, table, o);
  const auto c = pipeline::run_monte_carlo(kind_default, table, o);
  ASSERT_EQ(a.names, b.names);
  ASSERT_EQ(a.samples.size(), 2u);
  double largest_difference_to_default_um = 0.0;
  for (size_t k = 0; k < a.samples.size(); ++k)
    for (size_t i = 0; i < a.names.size(); ++i) {
      // 1e-9 µm: the same draw up to the rounding of the interpolated constant.
      EXPECT_NEAR(a.samples[k].before[i], b.samples[k].before[i], 1e-9) << a.names[i];
      EXPECT_NEAR(a.samples[k].after[i], b.samples[k].after[i], 1e-9) << a.names[i];
      largest_difference_to_default_um = std::max(
          {largest_difference_to_default_um, std::abs(a.samples[k].before[i] - c.samples[k].before[i]),
           std::abs(a.samples[k].after[i] - c.samples[k].after[i])});
    }
  // The column replaces the kind's default (1 µm): an X positioning offset of 0.3·z µm moves the flanks by a
  // fraction of a µm — far above the 1e-9 µm of the equivalence.
  EXPECT_GT(largest_difference_to_default_um, 1e-3);
}
