// The geartopo program as a user runs it: outputs, exit codes (0 ok, 1 bad input, 2 bad usage), messages.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace {

struct CliResult {
  int code;
  std::string out, err;
};

CliResult run(const std::string& args) {
  const auto dir = std::filesystem::temp_directory_path();
  // Unique per process and call: ctest runs tests in parallel processes.
  static int calls = 0;
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(calls++);
  const auto out = dir / ("geartopo_cli_out_" + tag), err = dir / ("geartopo_cli_err_" + tag);
  const std::string cmd = std::string(GEARTOPO_BINARY) + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  CliResult r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

const std::string kScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

} // namespace

TEST(Cli, GearJsonHasTheDocumentedKeys) {
  const CliResult r = run("gear " + kScene + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"d_mm", "db_mm", "da_mm", "df_mm", "alpha_t_deg", "beta_b_deg", "lead_mm", "pbt_mm", "sn_mm",
                          "k", "Wk_mm"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_NEAR(j["d_mm"].get<double>(), 565.8033, 1e-4);
  EXPECT_NEAR(j["alpha_t_deg"].get<double>(), 22.7959, 1e-4);
  EXPECT_EQ(j["hand"], "right");
  EXPECT_GT(j["lead_mm"].get<double>(), 0.0);
}

TEST(Cli, GearTableMarksAssumedValues) {
  const CliResult r = run("gear " + kScene);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("face width"), std::string::npos);
  EXPECT_NE(r.out.find("assumed"), std::string::npos);
  EXPECT_NE(r.out.find("W_k"), std::string::npos);
}

TEST(Cli, GearMeshIsWritten) {
  const auto mesh = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_cli_gear.off");
  std::filesystem::remove(mesh);
  const CliResult r = run("gear " + kScene + " --json --mesh " + mesh.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::file_size(mesh) > 1000);
  EXPECT_TRUE(nlohmann::json::accept(r.out)); // stdout stays one JSON object
  std::filesystem::remove(mesh);
}

TEST(Cli, BadInputExitsOneWithALocatedMessage) {
  const auto bad = write_temp("geartopo_bad.yaml", "gear:\n  normal_module_mm: 14\n  teeth: 35\n"
                                                   "  normal_pressure_angle_deg: 20\n  helix_angle_deg: 95\n"
                                                   "  profile_shift: 0\n  face_width_mm: 10\n");
  const CliResult r = run("gear " + bad.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(bad.string() + ":5:20: gear.helix_angle_deg: 95 is outside [-45, 45]"), std::string::npos)
      << r.err;
  EXPECT_EQ(run("gear /nonexistent.yaml").code, 1);
}

TEST(Cli, BadUsageExitsTwo) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("gear").code, 2);
  EXPECT_EQ(run("gear " + kScene + " --bogus").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("gear " + kScene + " --mesh /tmp/x.xyz").code, 2);
}

TEST(Cli, HelpExitsZeroForEverySubcommand) {
  const CliResult top = run("--help");
  EXPECT_EQ(top.code, 0);
  EXPECT_NE(top.out.find("gear"), std::string::npos);
  const CliResult gear = run("gear --help");
  EXPECT_EQ(gear.code, 0);
  EXPECT_NE(gear.out.find("--mesh"), std::string::npos);
}
