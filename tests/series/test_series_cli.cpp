// The CLI's side of issue 41: `evaluate --aqdef` writes the values of its iso1328.json as AQDEF characteristics (read
// back with the strict reader), and `series` refuses a bad series file with its file and line, exit code 1.
#include "cli_run.hpp"

#include "geartopo/aqdef/aqdef.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>

#include <unistd.h>

using namespace geartopo;

namespace {

struct CliFolder {
  std::filesystem::path dir;
  CliFolder() {
    dir = std::filesystem::temp_directory_path() /
          fmt::format("geartopo_series_cli_{}_{}", ::testing::UnitTest::GetInstance()->current_test_info()->name(), ::getpid());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  ~CliFolder() { std::filesystem::remove_all(dir); }
};

} // namespace

TEST(SeriesCli, EvaluateAqdefHoldsTheValuesOfIso1328Json) {
  CliFolder f;
  const std::string scene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";
  const auto run = test::run_geartopo(fmt::format("evaluate {} --method linear --out {} --aqdef {}", scene,
                                                  (f.dir / "out").string(), (f.dir / "gear.dfq").string()),
                                      f.dir);
  ASSERT_EQ(run.code, 0) << run.err;
  std::ifstream in(f.dir / "out" / "iso1328.json");
  const auto iso = nlohmann::json::parse(in);
  const aqdef::Part part = aqdef::read_dfq(f.dir / "gear.dfq");
  std::map<std::string, const aqdef::Characteristic*> by_code;
  for (const auto& c : part.characteristics) by_code[c.code] = &c;
  const auto& flanks = iso["before"]["flanks"];
  // The evaluated gear has every tooth: f_p and F_p per side and F_r follow the flanks, each its one value.
  const auto& gear = iso["before"]["gear"];
  ASSERT_EQ(part.characteristics.size(), 6 * flanks.size() + 5);
  for (const auto& [code, value] : std::map<std::string, double>{
           {"fp_L", gear["pitch"]["left"]["f_p_um"].get<double>()}, {"Fp_L", gear["pitch"]["left"]["F_p_um"].get<double>()},
           {"fp_R", gear["pitch"]["right"]["f_p_um"].get<double>()}, {"Fp_R", gear["pitch"]["right"]["F_p_um"].get<double>()},
           {"Fr", gear["F_r_um"].get<double>()}}) {
    ASSERT_EQ(by_code.at(code)->values.size(), 1u) << code;
    EXPECT_NEAR(by_code.at(code)->values[0].value, value, 0.5e-4) << code;
    EXPECT_EQ(by_code.at(code)->values[0].part_ident, "") << "evaluate names no gear";
  }
  for (const auto& fl : flanks) {
    const std::string suffix = fmt::format("_T{:02}_{}", fl["tooth"].get<int>(), fl["flank"] == "left" ? "L" : "R");
    for (const auto& [code, key] : std::map<std::string, std::string>{{"Fa", "F_alpha_um"}, {"ffa", "f_falpha_um"},
                                                                       {"fHa", "f_Halpha_um"}, {"Fb", "F_beta_um"},
                                                                       {"ffb", "f_fbeta_um"}, {"fHb", "f_Hbeta_um"}}) {
      const auto* c = by_code.at(code + suffix);
      ASSERT_EQ(c->values.size(), 1u) << code + suffix;
      EXPECT_NEAR(c->values[0].value, fl[key].get<double>(), 0.5e-4) << code + suffix; // 4 decimals
      EXPECT_EQ(c->nominal, 0.0);
    }
  }
}

TEST(SeriesCli, BadSeriesFileExitsOneNamingItsLine) {
  CliFolder f;
  std::ofstream(f.dir / "bad.yaml") << "scene: " << GEARTOPO_SOURCE_DIR << "/scenes/skmc1200w-mn14-z35.yaml\n"
                                    << "gears:\n  - measurement: a.csv\n    start_s: 0\n    colour: red\n";
  const auto run = test::run_geartopo(fmt::format("series {} --out {}", (f.dir / "bad.yaml").string(),
                                                  (f.dir / "out").string()),
                                      f.dir);
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.err.find("bad.yaml:5:"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("colour"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(f.dir / "out" / "series.json"));
}

// `report SERIES` takes SCENE and --out only: the series file names the gears' measurements and its spec the rest, so
// a flag of the scene's report (the measurement, the ISO options, the Monte Carlo) is refused, never ignored.
TEST(SeriesCli, ReportOfASeriesRefusesTheSceneReportsFlags) {
  CliFolder f;
  std::ofstream(f.dir / "series.yaml") << "scene: " << GEARTOPO_SOURCE_DIR << "/scenes/skmc1200w-mn14-z35.yaml\n"
                                       << "gears:\n  - measurement: a.csv\n    start_s: 0\n";
  for (const std::string flag : {"--samples 10", "--iso-direction normal", "--measured a.csv", "--max-time-s 5"}) {
    const auto run = test::run_geartopo(fmt::format("report {} --out {} {}", (f.dir / "series.yaml").string(),
                                                    (f.dir / "out").string(), flag),
                                        f.dir);
    EXPECT_EQ(run.code, 2) << flag << ": " << run.err;
    EXPECT_NE(run.err.find(flag.substr(0, flag.find(' ')) + ": has no effect"), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(f.dir / "out" / "index.html")) << flag;
  }
}
