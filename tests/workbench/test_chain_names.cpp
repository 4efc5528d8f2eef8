// geartopo tests — a chain's own component and axis names in a scene (issue 42): error tables, constants,
// uncertainties and machine changes refer to the components as the scene's chain names them, and a name of another
// chain is refused at its file, line and field.
//
// The chain: the CFXZAY's geometry with the radial slide called U (tool side: U along +x, Z, A, Y). ISO 841's letter
// order puts it in pose slot 2 (Y, Z, U, A, C), so its positioning error is `delta_xu` in slot 2's block, and the
// physics is the CFXZAY's X: a constant δ of it grinds the flanks the CFXZAY's X error does.
// Units: mm, µm.
#include "geartopo/grinding/chain_process.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/workbench/workbench.hpp"

#include "../chain_scene_fixture.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include <unistd.h>

using namespace geartopo;
using namespace geartopo::chain_fixture;

namespace chain_names_test {

const std::string kScene = kGearAndWheel + R"(machine:
  chain:
    name: CFUZAY
    workpiece:
      - {name: C, kind: rotary, direction: [0, 0, 1]}
    tool:
      - {name: U, kind: linear, direction: [1, 0, 0], stroke_mm: [0, 900]}
      - {name: Z, kind: linear, direction: [0, 0, 1], stroke_mm: [0, 800]}
      - {name: A, kind: rotary, direction: [1, 0, 0], stroke_deg: [-45, 45]}
      - {name: Y, kind: linear, direction: [0, 1, 0], stroke_mm: [-200, 200]}
)";

} // namespace chain_names_test

using namespace chain_names_test;

TEST(ChainNames, TheChainsOwnNamesAreReadAndOthersRefusedAtTheirLine) {
  const auto sc = scene::parse_scene(kScene + "  constants: {delta_xu_um: 10}\n  uncertainty: {components: {S_uz_urad: 2}}\n"
                                              "  strokes: {u_mm: [100, 800]}\n", "mem");
  const auto& chain = *sc.machine.chain;
  ASSERT_EQ(chain.axis_name(machine::Axis::Z), "U"); // slot 2
  ASSERT_EQ(sc.machine.sources.size(), 1u);
  EXPECT_EQ(chain.info(sc.machine.sources[0].id()).name, "delta_xu");
  EXPECT_EQ(sc.machine.strokes.z_mm.min, 100.0); // slot 2's stroke
  EXPECT_EQ(chain.axis(machine::Axis::Z).stroke->min, 100.0);
  const auto s_uz = chain.component_from_name("S_uz");
  ASSERT_TRUE(s_uz);
  EXPECT_NEAR(sc.machine.uncertainty.component_u[static_cast<std::size_t>(machine::index(*s_uz))], 2e-6, 1e-18);

  // Lines: the scene above has 20; the added keys start at 21.
  const auto constant = workbench_error_of(kScene + "  constants: {delta_xx_um: 10}\n");
  EXPECT_NE(constant.find("scenes/x.yaml:21:"), std::string::npos) << constant;
  EXPECT_NE(constant.find("machine.constants.delta_xx_um: 'delta_xx' is not an error component of the CFUZAY chain"),
            std::string::npos) << constant;
  const auto change = workbench_error_of(kScene + "machine_changes:\n  - {component: E_XOC, law: constant, change_um: 1}\n"
                                        "  - {component: S_xy, law: constant, change_urad: 1}\n");
  EXPECT_NE(change.find(":23:"), std::string::npos) << change;
  EXPECT_NE(change.find("machine_changes[1].component: 'S_xy' is not an error component of the CFUZAY chain"),
            std::string::npos) << change;
  const auto stroke = workbench_error_of(kScene + "  strokes: {x_mm: [0, 900]}\n");
  EXPECT_NE(stroke.find("machine.strokes.x_mm"), std::string::npos) << stroke;
}

TEST(ChainNames, ErrorTablesNameTheChainsAxesAndComponents) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_chain_names_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "u.csv") << "u_mm,delta_xu_um,epsilon_zu_urad\n0,10,0\n900,10,0\n";
  std::ofstream(dir / "x.csv") << "x_mm,delta_xx_um\n0,10\n900,10\n";
  std::ofstream(dir / "s.yaml") << kScene << "  tables: [u.csv]\n";
  const workbench::Workbench wb(dir / "s.yaml");
  // The radial slide's 10 µm, read from the chain's table into pose slot 2, grinds the flanks the CFXZAY's X does
  // with 10 µm in slot 0 (the compiled-in MachineProcess): to 1e-4 µm (the exact search converges to 1e-6 µm).
  std::ofstream(dir / "seed.yaml") << kScene.substr(0, kScene.find("machine:")) << "machine:\n  tables: [x.csv]\n";
  const workbench::Workbench seed(dir / "seed.yaml");
  const auto u = grid_deviations(wb), x = grid_deviations(seed);
  ASSERT_EQ(u.size(), x.size());
  for (std::size_t i = 0; i < u.size(); ++i) EXPECT_NEAR(u[i], x[i], 1e-4) << i;
  EXPECT_GT(*std::max_element(x.begin(), x.end()), 1.0); // the error does reach the flanks

  std::ofstream(dir / "s.yaml") << kScene << "  tables: [x.csv]\n";
  try {
    const workbench::Workbench bad(dir / "s.yaml");
    FAIL() << "accepted a CFXZAY table on the CFUZAY";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "x.csv").string());
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(std::string(e.what()).find("with axis y, z, u, a or c"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}
