// The geartopo program on a scene whose machine is another kinematic chain (issue 42: scenes/cafxzy-mn14-z35.yaml,
// the CAFXZY preset): simulate and evaluate run and write their files; a chain the path cannot reach exits 1 naming
// the point and the axis.
#include "../cli_run.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>
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
