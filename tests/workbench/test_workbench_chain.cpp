// geartopo tests — the workbench builds the grinding process from the scene's chain (issue 42): the CFXZAY keeps
// MachineProcess, any other chain grinds through a ChainProcess whose path is checked at set-up.
//
// Physics: a constant positioning error δ of the X slide moves the wheel away from the gear along the centre distance
// on both layouts (on the CAFXZY the A table tilts about x, which leaves x alone; the C table turns the gear and the
// setting alike), so both grind the same flanks.
// Units: mm, µm.
#include "geartopo/compensation/compensator.hpp"
#include "geartopo/grinding/chain_process.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/twist.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/workbench/workbench.hpp"

#include "../chain_scene_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

using namespace geartopo;
using namespace geartopo::chain_fixture;

TEST(WorkbenchChain, TheCfxzayKeepsMachineProcessAnyOtherChainGrindsThroughItsChain) {
  const workbench::Workbench seed(scene::parse_scene(kGearAndWheel, "mem"));
  EXPECT_NE(dynamic_cast<const grinding::MachineProcess*>(&seed.machine_process), nullptr);
  const workbench::Workbench other(scene::parse_scene(kGearAndWheel + "machine:\n  chain: CAFXZY\n", "mem"));
  const auto* chain = dynamic_cast<const grinding::ChainProcess*>(&other.machine_process);
  ASSERT_NE(chain, nullptr);
  EXPECT_EQ(chain->chain().name(), "CAFXZY");
  EXPECT_EQ(chain->datum_face_z_mm(), 180.0); // the face width centred in Z [−300, 700]
}

TEST(WorkbenchChain, AConstantXErrorGrindsTheSameFlanksOnEitherLayout) {
  // Two evaluators (the compiled-in CFXZAY, the CAFXZY's chain as data with its inverse kinematics) of two layouts
  // whose X slide moves the wheel along the same line: the same flanks to 1e-4 µm (the exact search converges to
  // 1e-6 µm). The flanks thicken (plus material) by at most δ: a rigid move of δ shifts no surface point further.
  const double delta_um = 10.0;
  std::vector<std::vector<double>> dev;
  for (const std::string chain : {"CFXZAY", "CAFXZY"})
    dev.push_back(grid_deviations(workbench::Workbench(scene::parse_scene(
        kGearAndWheel + "machine:\n  chain: " + chain + "\n  constants: {delta_xx_um: 10}\n", "mem"))));
  ASSERT_EQ(dev[0].size(), dev[1].size());
  ASSERT_EQ(dev[0].size(), 100u);
  for (std::size_t i = 0; i < dev[0].size(); ++i) {
    EXPECT_NEAR(dev[1][i], dev[0][i], 1e-4) << i;
    EXPECT_GT(dev[0][i], 0.0) << i;
    EXPECT_LE(dev[0][i], delta_um) << i;
  }
}

TEST(WorkbenchChain, APathOutsideTheChainsStrokesIsRefusedAtTheChainNamingThePointAndTheAxis) {
  // Y = y + (z + 150)·sin α on the CAFXZY (docs/machine-model.md §9): 330…370 mm along the tilted gear axis at α = 15°
  // puts Y at 85…96 mm, outside ±20.
  const auto e = workbench_error_of(kGearAndWheel + "machine:\n  chain: CAFXZY\n  strokes: {y_mm: [-20, 20]}\n");
  EXPECT_NE(e.find("scenes/x.yaml:12:10: machine.chain: CAFXZY chain, space "), std::string::npos) << e;
  EXPECT_NE(e.find(": Y = "), std::string::npos) << e;
  EXPECT_NE(e.find("mm is outside its stroke [-20, 20] mm"), std::string::npos) << e;
  // Machine changes move the wheel by the CFXZAY's first-order twist (effects::ComponentChanges): refused elsewhere.
  const auto changes = workbench_error_of(kGearAndWheel + "machine:\n  chain: CAFXZY\nmachine_changes:\n"
                                                "  - {component: E_AOA, law: constant, change_urad: 5}\n");
  EXPECT_NE(changes.find("scenes/x.yaml:14:"), std::string::npos) << changes;
  EXPECT_NE(changes.find("machine_changes: machine changes act through the CFXZAY's error Jacobian only"),
            std::string::npos) << changes;
}

// The shipped CAFXZY scene (scenes/cafxzy-mn14-z35.yaml): its first-order pose error twist (the chain's 6×43 error
// Jacobian times the components) is the linearisation of its exact pose (the chain's error HTMs): at path points over
// the whole grinding order they differ by second-order terms, below 1 % of the twist (components of tens of µrad and
// a few µm: second order ~1e-4 of the first), as the CFXZAY's do (tests/effects, EveryEffect).
TEST(WorkbenchChain, TheShippedCafxzySceneFirstOrderTwistIsTheLinearisationOfTheExactPose) {
  const workbench::Workbench wb(std::filesystem::path(GEARTOPO_SOURCE_DIR) / "scenes/cafxzy-mn14-z35.yaml");
  ASSERT_NE(dynamic_cast<const grinding::ChainProcess*>(&wb.machine_process), nullptr);
  double worst = 0.0, size = 0.0;
  const auto& strokes = wb.setup.path().strokes();
  for (std::size_t k = 0; k < strokes.size(); k += 7)
    for (double f : {0.0, 0.5, 1.0}) {
      const auto& st = strokes[k];
      const auto pp = wb.setup.path().point(st.space, st.z_begin_mm + f * (st.z_end_mm - st.z_begin_mm));
      const machine::Vector6d exact =
          machine::pose_error_twist(wb.machine_process.actual_wMg(pp) * machine::ideal_wMg(pp.q).inverse());
      worst = std::max(worst, (wb.machine_process.error_twist_w(pp) - exact).cwiseAbs().maxCoeff());
      size = std::max(size, exact.cwiseAbs().maxCoeff());
    }
  EXPECT_GT(size, 1e-3); // mm or rad: the constants move the wheel by µm over the gear's 600 mm
  EXPECT_LT(worst, 0.01 * size);
}

// Compensation on the CAFXZY: a constant zero error E_AOA = 100 µrad of its A tilting table turns the C table, and
// the gear on it, rigidly about the A axis line (machine x, 150 mm below the C table's face): a tilt about the gear
// frame's x plus a translation. The setting's coordinates make exactly these motions (the cross angle turns about x;
// x, y, z translate), so the error is corrected completely: after the flank method's corrections (setting
// coordinates, turned into the chain's axes by its inverse kinematics in ChainProcess) the flanks are the error-free
// ones to 0.01 µm, while the error alone leaves tens of µm (100 µrad over the ~450 mm from the A axis to the flank).
TEST(WorkbenchChain, AConstantATableZeroErrorOfTheCafxzyIsCompensatedAway) {
  const workbench::Workbench wb(
      scene::parse_scene(kGearAndWheel + "machine:\n  chain: CAFXZY\n  constants: {E_AOA_urad: 100}\n", "mem"));
  compensation::CompensationOptions o;
  o.step_mm = 5.0;
  const auto table = compensation::compute_corrections(wb.setup, wb.process(), {wb.machine, 180.0}, o);
  const compensation::CompensatedProcess corrected(wb.process(), table, compensation::CorrectedPose::Exact);
  grinding::SimulationOptions so;
  so.teeth = {1, 16};
  so.rows = 5, so.cols = 5, so.profile_points = 2, so.helix_points = 2;
  const auto largest = [&](const grinding::GrindingProcess& p) {
    double m = 0.0;
    for (const auto& flank : grinding::simulate_topology(wb.setup, p, so))
      for (const auto& g : flank.grid) m = std::max(m, std::abs(g.deviation_um));
    return m;
  };
  const double before = largest(wb.process()), after = largest(corrected);
  EXPECT_GT(before, 10.0);
  EXPECT_LT(after, 0.01);
}
