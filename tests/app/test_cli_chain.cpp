// The geartopo program on a scene whose machine is another kinematic chain (issue 42: scenes/cafxzy-mn14-z35.yaml,
// the CAFXZY preset): simulate and evaluate run and write their files; a chain the path cannot reach exits 1 naming
// the point and the axis.
#include "../cli_run.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>
#include <unistd.h>

namespace {

const std::string kCafxzy = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/cafxzy-mn14-z35.yaml";

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

} // namespace

TEST(CliChain, ACafxzySceneSimulatesAndEvaluates) {
  const auto dir = fresh_dir("geartopo_cli_chain");
  const auto sim = geartopo::test::run_geartopo("simulate " + kCafxzy + " --out " + (dir / "sim").string() +
                                                    " --teeth 1,18 --method exact --quiet", dir);
  ASSERT_EQ(sim.code, 0) << sim.err;
  std::ifstream topo(dir / "sim" / "topology.csv");
  int lines = 0;
  for (std::string l; std::getline(topo, l);) ++lines;
  EXPECT_EQ(lines, 1 + 4 * 63);

  const auto eval = geartopo::test::run_geartopo("evaluate " + kCafxzy + " --out " + (dir / "eval").string() +
                                                     " --method linear --quiet", dir);
  ASSERT_EQ(eval.code, 0) << eval.err;
  std::ifstream in(dir / "eval" / "iso1328.json");
  const auto j = nlohmann::json::parse(in)["before"];
  EXPECT_EQ(j["flanks"].size(), 70u);
  EXPECT_FALSE(j["classification"]["overall"].is_null());
  std::filesystem::remove_all(dir);
}

TEST(CliChain, APathTheChainCannotReachExitsOneNamingThePointAndTheAxis) {
  const auto dir = fresh_dir("geartopo_cli_chain_bad");
  std::ifstream in(kCafxzy);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "  chain: CAFXZY ";
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  // Y = y + (z + 150)·sin α: 440…610 mm along the gear axis at α = 30° need Y = 220…305 mm.
  text.insert(at, "  strokes: {y_mm: [-200, 200]}\n");
  std::ofstream(dir / "s.yaml") << text;
  const auto r = geartopo::test::run_geartopo("simulate " + (dir / "s.yaml").string() + " --out " +
                                                  (dir / "out").string() + " --quiet", dir);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("machine.chain: CAFXZY chain, space "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Y = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("is outside its stroke [-200, 200] mm"), std::string::npos) << r.err;
  std::filesystem::remove_all(dir);
}

namespace {

/// One CSV line split at commas.
std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> f;
  std::stringstream in(line);
  for (std::string s; std::getline(in, s, ',');) f.push_back(s);
  return f;
}

/// The shipped CAFXZY scene with its constants replaced by `constants` (a YAML flow map).
std::string cafxzy_with_constants(const std::string& constants) {
  std::ifstream in(kCafxzy);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto from = text.find("  constants:");
  const auto to = text.find("\nwheel:");
  if (from == std::string::npos || to == std::string::npos) return {};
  return text.substr(0, from) + "  constants: " + constants + "\n" + text.substr(to);
}

} // namespace

// `geartopo compensate` on the CAFXZY with a constant A-table zero error (100 µrad) and a constant y-straightness of
// the Z slide (8 µm) alone: the corrections are written in the chain's own axes, ΔA = −100 µrad and ΔY = −8 µm at every
// row with X, Z, C untouched (each error undone by one axis: the table turns to A + E_AOA, the Y slide rides on Z with
// no rotary axis between them), within the chain's strokes; the gear, tens of µm off before, comes out error-free.
TEST(CliChain, CompensateCorrectsConstantErrorsOfTheCafxzyInItsOwnAxes) {
  const auto dir = fresh_dir("geartopo_cli_chain_comp");
  const std::string scene = cafxzy_with_constants("{E_AOA_urad: 100, delta_yz_um: 8}");
  ASSERT_FALSE(scene.empty());
  std::ofstream(dir / "s.yaml") << scene;
  const auto r = geartopo::test::run_geartopo("compensate " + (dir / "s.yaml").string() + " --out " +
                                                  (dir / "out").string() + " --step 10 --quiet", dir);
  ASSERT_EQ(r.code, 0) << r.err;

  std::ifstream csv(dir / "out" / "corrections.csv");
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line, "space,z_stroke_mm,time_s,X_mm,Y_mm,Z_mm,A_deg,C_deg,dX_um,dY_um,dZ_um,dA_urad,dC_urad,within_strokes");
  int rows = 0;
  std::set<int> spaces;
  while (std::getline(csv, line)) {
    const auto f = fields_of(line);
    ASSERT_EQ(f.size(), 14u) << line;
    ++rows;
    spaces.insert(std::stoi(f[0]));
    EXPECT_NEAR(std::stod(f[8]), 0.0, 0.01) << line;    // dX_um
    EXPECT_NEAR(std::stod(f[9]), -8.0, 0.01) << line;   // dY_um
    EXPECT_NEAR(std::stod(f[10]), 0.0, 0.01) << line;   // dZ_um
    EXPECT_NEAR(std::stod(f[11]), -100.0, 0.01) << line; // dA_urad
    EXPECT_NEAR(std::stod(f[12]), 0.0, 0.01) << line;   // dC_urad
    EXPECT_EQ(f[13], "yes") << line;
    // The A table tilts the gear by the cross angle, which for a form wheel is the gear's helix angle (30°), the same
    // at every row: the chain's own A, not the setting's z or y.
    EXPECT_NEAR(std::abs(std::stod(f[6])), 30.0, 1e-6) << line;
  }
  EXPECT_EQ(spaces.size(), 35u);
  EXPECT_GE(rows, 35 * 2);

  std::ifstream in(dir / "out" / "iso1328.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_GT(j["largest_abs_deviation_um"]["before"].get<double>(), 10.0);
  EXPECT_LT(j["largest_abs_deviation_um"]["nominal_after"].get<double>(), 0.01);
  EXPECT_EQ(j["compensation"]["rows_outside_strokes"].get<int>(), 0);
  std::filesystem::remove_all(dir);
}

// The ISG table is the CFXZAY's (its grid over X, Y, Z): asked for on another chain, compensate exits with a usage
// error naming the option and the chain, before any work.
TEST(CliChain, CompensateRefusesTheIsgTableOnAnotherChain) {
  const auto dir = fresh_dir("geartopo_cli_chain_isg");
  const auto r = geartopo::test::run_geartopo("compensate " + kCafxzy + " --out " + (dir / "out").string() +
                                                  " --isg-table --quiet", dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("--isg-table"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("CAFXZY"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "corrections.csv"));
  std::filesystem::remove_all(dir);
}
