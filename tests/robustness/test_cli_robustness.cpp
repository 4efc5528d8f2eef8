// The geartopo program on broken inputs from the corpus: exit code 1 (bad input), one clear message on stderr naming
// the file, never a crash or a signal. (Exit 2 is bad usage, e.g. an out-of-range --dense.)
#include "robustness_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

using namespace geartopo::robustness;
namespace fs = std::filesystem;

namespace {

struct CliResult {
  int code; ///< exit code; -1 when killed by a signal
  std::string out, err;
};

CliResult run(const std::string& args) {
  static int calls = 0;
  const std::string tag = std::to_string(calls++);
  const auto out = temp_path("cli_out_" + tag), err = temp_path("cli_err_" + tag);
  // `timeout` turns a hang into exit 124 instead of stalling the suite.
  const std::string cmd = "timeout 120 " + std::string(GEARTOPO_BINARY) + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  CliResult r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  fs::remove(out);
  fs::remove(err);
  return r;
}

std::string corpus(const std::string& rel) { return (kCorpus / rel).string(); }

void expect_bad_input(const CliResult& r, const std::string& file) {
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("error"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(fs::path(file).filename().string()), std::string::npos) << "stderr does not name " << file << ": " << r.err;
}

class CliScene : public ::testing::TestWithParam<std::string> {};

} // namespace

TEST_P(CliScene, GearExitsWithCode1AndAMessage) {
  const std::string scene = corpus("scenes/" + GetParam());
  expect_bad_input(run("gear " + scene), GetParam());
}

TEST_P(CliScene, SimulateExitsWithCode1AndAMessage) {
  const std::string scene = corpus("scenes/" + GetParam());
  const auto out = temp_path("cli_sim");
  // The table fragment names the table, not the scene: check for either.
  const auto r = run("simulate " + scene + " --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_FALSE(r.err.empty());
  fs::remove_all(out);
}

INSTANTIATE_TEST_SUITE_P(Corpus, CliScene,
                         ::testing::Values("syntax_unclosed_bracket.yaml", "nan_module.yaml", "inf_face_width.yaml",
                                           "empty.yaml", "binary_junk.yaml", "deeply_nested_lists.yaml",
                                           "long_line_number.yaml", "undercut.yaml", "pointed_tip.yaml",
                                           "grid_huge_1e10.yaml", "unknown_key_typo.yaml", "module_0.yaml"),
                         [](const auto& info) {
                           std::string n = info.param.substr(0, info.param.find('.'));
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

TEST(Cli, ASceneWithABrokenTableNamesTheTable) {
  const auto r = run("gear " + corpus("scenes/table_c_not_closed.yaml"));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("c_not_closed.csv"), std::string::npos) << r.err;
}

TEST(Cli, CompareRefusesABrokenTopologyFile) {
  const std::string file = corpus("topology/nan_deviation.csv");
  const auto out = temp_path("cli_compare");
  expect_bad_input(run("compare " + kDefaultScene.string() + " --measured " + file + " --out " + out.string()), file);
  fs::remove_all(out);
}

TEST(Cli, DiagnoseRefusesABrokenPointCloud) {
  const std::string file = corpus("point_clouds/duplicate_point.csv");
  const auto out = temp_path("cli_diagnose");
  expect_bad_input(run("diagnose " + kDefaultScene.string() + " --measured " + file + " --out " + out.string()), file);
  fs::remove_all(out);
}

TEST(Cli, EvaluateRefusesABrokenTracesFile) {
  const std::string file = corpus("topology/traces_not_increasing.csv");
  const auto out = temp_path("cli_evaluate");
  expect_bad_input(run("evaluate " + kDefaultScene.string() + " --traces " + file + " --out " + out.string()), file);
  fs::remove_all(out);
}

TEST(Cli, AnOversizedDenseGridOnTheCommandLineIsBadUsage) {
  const auto out = temp_path("cli_dense");
  const auto r = run("simulate " + kDefaultScene.string() + " --dense 100000x100000 --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--dense"), std::string::npos) << r.err;
  fs::remove_all(out);
}

// A grid that fits per flank (3.8e6 points) but not for all 70 flanks (2.7e8 > grinding::kMaxPointsPerSimulation)
// loads, and `simulate` refuses it at once (exit 1, before allocating) instead of running out of memory.
TEST(Cli, SimulateRefusesAGridTooLargeForAllFlanksBeforeAllocating) {
  const auto scene = temp_path("big_grid.yaml");
  std::ofstream(scene) << "gear:\n  normal_module_mm: 14\n  teeth: 35\n  normal_pressure_angle_deg: 20\n"
                          "  helix_angle_deg: 30\n  profile_shift: 0.274\n  face_width_mm: 150\n"
                          "measurement:\n  dense_rows: 1900\n  dense_cols: 2000\n";
  const auto out = temp_path("cli_big_grid");
  const auto r = run("simulate " + scene.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.err;
  // Refused by the size check (before allocating: Simulation.HugeGridsAreRefusedBeforeAllocating), not by running out
  // of memory; a hang would hit the test's timeout.
  EXPECT_NE(r.err.find("is more than a simulation may hold"), std::string::npos) << r.err;
  fs::remove_all(out);
  fs::remove(scene);
}
