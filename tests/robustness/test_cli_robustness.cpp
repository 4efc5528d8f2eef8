// The geartopo program on broken inputs from the corpus: exit code 1 (bad input), one clear message on stderr naming
// the file, never a crash or a signal. (Exit 2 is bad usage, e.g. an out-of-range --dense.)
#include "robustness_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <sys/wait.h>

using namespace geartopo::robustness;
namespace fs = std::filesystem;

namespace {

struct CliResult {
  int code; ///< exit code; -1 when killed by a signal
  std::string out, err;
};

// `shell_prefix` runs first in the same shell (e.g. a file-size limit that the program inherits).
CliResult run(const std::string& args, const std::string& shell_prefix = "") {
  static int calls = 0;
  const std::string tag = std::to_string(calls++);
  const auto out = temp_path("cli_out_" + tag), err = temp_path("cli_err_" + tag);
  // `timeout` turns a hang into exit 124 instead of stalling the suite: 120 s per command, times the build's
  // GEARTOPO_TEST_TIMEOUT_FACTOR (4 under scripts/sanitize.sh, where one compensate of the default scene took > 120 s).
  std::string cmd = shell_prefix;
  cmd += "timeout " + std::to_string(120 * GEARTOPO_TEST_TIMEOUT_FACTOR) + " ";
  cmd += GEARTOPO_BINARY;
  cmd += " " + args + " >" + out.string() + " 2>" + err.string();
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
                                           "grid_huge_1e10.yaml", "unknown_key_typo.yaml", "module_0.yaml",
                                           "process_feed_denormal.yaml", "process_feed_tiny.yaml"),
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

// Issue 18: a 1e300 µm deviation crashed `diagnose` (SIGSEGV in the effect fit); a denormal feed crashed
// `run`, `report` and `diagnose` and wrote inf into `compensate`'s time_s.
TEST(Cli, DiagnoseRefusesAnAbsurdDeviationAtItsLine) {
  const std::string file = corpus("topology/huge_deviation.csv");
  const auto out = temp_path("cli_diagnose_huge");
  const auto r = run("diagnose " + kDefaultScene.string() + " --measured " + file + " --out " + out.string());
  expect_bad_input(r, file);
  EXPECT_NE(r.err.find("huge_deviation.csv:4:"), std::string::npos) << r.err;
  fs::remove_all(out);
}

TEST(Cli, EveryCommandRefusesADenormalFeed) {
  const std::string scene = corpus("scenes/process_feed_denormal.yaml");
  const auto out = temp_path("cli_feed");
  for (const std::string cmd : {"run", "report", "compensate", "diagnose"}) {
    std::string args = cmd + " " + scene + " --out " + out.string();
    if (cmd == "diagnose") args += " --measured " + corpus("topology/nan_deviation.csv");
    const auto r = run(args);
    EXPECT_EQ(r.code, 1) << cmd << ": " << r.err;
    EXPECT_NE(r.err.find("process_feed_denormal.yaml:9:"), std::string::npos) << cmd << ": " << r.err;
    fs::remove_all(out);
  }
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

// A grid within the scene's per-key bound (1000 × 1000 points per flank) but not for all 120 flanks of a 60-tooth gear
// (1.2e8 > grinding::kMaxPointsPerSimulation = 1e8)
// loads, and `simulate` refuses it at once (exit 1, before allocating) instead of running out of memory.
TEST(Cli, SimulateRefusesAGridTooLargeForAllFlanksBeforeAllocating) {
  const auto scene = temp_path("big_grid.yaml");
  std::ofstream(scene) << "gear:\n  normal_module_mm: 14\n  teeth: 60\n  normal_pressure_angle_deg: 20\n"
                          "  helix_angle_deg: 30\n  profile_shift: 0.274\n  face_width_mm: 150\n"
                          "measurement:\n  dense_rows: 1000\n  dense_cols: 1000\n";
  const auto out = temp_path("cli_big_grid");
  const auto r = run("simulate " + scene.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.err;
  // Refused by the size check (before allocating: Simulation.HugeGridsAreRefusedBeforeAllocating), not by running out
  // of memory; a hang would hit the test's timeout.
  EXPECT_NE(r.err.find("is more than a simulation may hold"), std::string::npos) << r.err;
  fs::remove_all(out);
  fs::remove(scene);
}

// Issue 18: a directory as the scene gave "empty scene", as the measurement "1:1: header: missing header";
// /dev/zero or a FIFO hung the program. Each is now refused by name at once (exit 1).
TEST(Cli, SpecialFilesAsSceneOrMeasurementAreRefusedByName) {
  const auto dir = temp_path("cli_dir");
  const auto fifo = temp_path("cli_fifo");
  const auto out = temp_path("cli_special_out");
  fs::create_directories(dir);
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto r = run("gear " + dir.string());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find(dir.string() + ": is a directory, not a scene file"), std::string::npos) << r.err;
  r = run("gear " + fifo.string());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("is a FIFO"), std::string::npos) << r.err;
  for (const std::string& measured : {dir.string(), fifo.string(), std::string("/dev/zero"), std::string("/dev/urandom")}) {
    r = run("diagnose " + kDefaultScene.string() + " --measured " + measured + " --out " + out.string());
    EXPECT_EQ(r.code, 1) << measured << ": " << r.err;
    EXPECT_NE(r.err.find(measured + ": is a"), std::string::npos) << r.err;
    fs::remove_all(out);
  }
  fs::remove(fifo);
  fs::remove_all(dir);
}

// Issue 18, numeric flags: CLI::Range let NaN through; inf and 1e308 poses, empty and duplicate tooth lists and a
// negative seed were accepted. Each is bad usage (exit 2) naming its flag.
TEST(Cli, NonFiniteOrOutOfRangeFlagsAreBadUsageNamingTheFlag) {
  const std::string scene = kDefaultScene.string();
  const auto out = temp_path("cli_flags");
  const std::vector<std::pair<std::string, std::string>> cases{
      {"synth " + scene + " --out " + out.string() + "/m.csv --noise-um nan", "--noise-um"},
      {"diagnose " + scene + " --measured " + corpus("topology/nan_deviation.csv") + " --out " + out.string() + " --noise-um nan", "--noise-um"},
      {"compare " + scene + " --measured " + corpus("topology/nan_deviation.csv") + " --out " + out.string() + " --noise-um inf", "--noise-um"},
      {"compensate " + scene + " --out " + out.string() + " --step nan", "--step"},
      {"machine " + scene + " --pose nan,0,0,0,0", "--pose"},
      {"machine " + scene + " --pose 500,0,inf,0,0", "--pose"},
      {"machine " + scene + " --pose 1e308,0,0,0,0", "--pose"},
      {"synth " + scene + " --out " + out.string() + "/m.csv --teeth \"\"", "--teeth"},
      {"synth " + scene + " --out " + out.string() + "/m.csv --teeth 1,1", "--teeth"},
      {"simulate " + scene + " --out " + out.string() + " --teeth 1,1", "--teeth"},
      {"simulate " + scene + " --out " + out.string() + " --teeth \"\"", "--teeth"},
      {"synth " + scene + " --out " + out.string() + "/m.csv --seed -1", "--seed"},
      {"simulate " + scene + " --out " + out.string() + " --dense 2000x2000", "--dense"},
      {"simulate " + scene + " --out \"\"", "--out"},
      {"evaluate " + scene + " --out \"\"", "--out"},
      {"synth " + scene + " --out \"\"", "--out"},
  };
  for (const auto& [args, flag] : cases) {
    const auto r = run(args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(flag), std::string::npos) << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(out / "m.csv"));
  fs::remove_all(out);
}

// Issue 18, outputs: `synth --out /dev/full` "succeeded"; a full disk left half-written files under their final
// names. The file-size limit (SIGXFSZ ignored, so write() fails with EFBIG as on a full disk) works for root too.
TEST(Cli, SynthRefusesADeviceAsItsOutput) {
  const auto r = run("synth " + kDefaultScene.string() + " --out /dev/full --teeth 1");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("/dev/full: cannot write"), std::string::npos) << r.err;
}

TEST(Cli, AFullDiskFailsNamingTheFileAndLeavesNoPartialFile) {
  const auto out = temp_path("cli_full_disk");
  fs::remove_all(out);
  const auto r = run("simulate " + kDefaultScene.string() + " --teeth 1 --method linear --out " + out.string(),
                     "trap '' XFSZ; ulimit -f 2; ");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("topology.csv: cannot write"), std::string::npos) << r.err;
  // No temporary, no staging folder, and not the folder itself: the failed run created it, and removes it.
  EXPECT_FALSE(fs::exists(out)) << "the failed run left its folder";
  fs::remove_all(out);

  const auto file = temp_path("cli_full_disk.csv");
  const auto s = run("synth " + kDefaultScene.string() + " --teeth 1 --out " + file.string(), "trap '' XFSZ; ulimit -f 2; ");
  EXPECT_EQ(s.code, 1) << s.err;
  EXPECT_NE(s.err.find(file.string() + ": cannot write"), std::string::npos) << s.err;
  EXPECT_FALSE(fs::exists(file));
}

// Issue 18, warnings: an angular error of the A axis about y (epsilon_ya, 200 µrad) leaves the flank untouched
// (largest |deviation| 0.000 µm), but the paper's pseudo-inverse cancels it through the other axes and spoils the
// gear (≈ 14 µm; the same mechanism as Compensation.SpinAboutTheWheelAxisIsNotFought).
// `compensate` said "improvement" and nothing else; it now warns on stderr and in iso1328.json.
TEST(Cli, CompensationThatMakesTheGearWorseIsWarnedAbout) {
  const auto scene = temp_path("worse.yaml");
  std::ofstream(scene) << "gear:\n  normal_module_mm: 14\n  teeth: 35\n  normal_pressure_angle_deg: 20\n"
                          "  helix_angle_deg: 30\n  profile_shift: 0.274\n  face_width_mm: 150\n"
                          "machine:\n  constants:\n    epsilon_ya_urad: 200\n";
  const auto out = temp_path("cli_worse");
  auto json = [&] {
    std::ifstream in(out / "iso1328.json");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  auto r = run("compensate " + scene.string() + " --method paper --out " + out.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: compensation made the gear worse"), std::string::npos) << r.err;
  EXPECT_NE(json().find("\"warnings\": [\n    \"compensation made the gear worse"), std::string::npos) << json();
  // The flank method fixes the same gear: no warning, an empty list.
  r = run("compensate " + scene.string() + " --method flank --out " + out.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(json().find("\"warnings\": []"), std::string::npos) << json();
  fs::remove_all(out);
  fs::remove(scene);
}

// Issues 18 and 25, work estimate: a long simulation announces itself on a terminal (run under `script`, which gives
// the program a pseudo-terminal) and into a log alike (stderr a file: a log of a long job should say its cost too).
TEST(Cli, ALongSimulationPrintsAnEstimateOnATerminalAndIntoALog) {
  const auto out = temp_path("cli_estimate");
  const std::string args = "simulate " + kDefaultScene.string() + " --teeth 1 --method linear --dense 710x710 --out " + out.string();
  const auto plain = run(args);
  EXPECT_EQ(plain.code, 0) << plain.err;
  EXPECT_NE(plain.err.find("geartopo: 1008826 points on 2 flanks (linear): about 0.3 s on 2 cores"), std::string::npos)
      << plain.err;
  const auto log = temp_path("cli_estimate.log");
  if (std::system("command -v script >/dev/null 2>&1") != 0) GTEST_SKIP() << "no `script` (util-linux) to make a terminal";
  std::string cmd = "script -qec '";
  cmd += GEARTOPO_BINARY;
  cmd += " " + args + "' /dev/null >" + log.string() + " 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream in(log);
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_NE(s.str().find("geartopo: 1008826 points on 2 flanks (linear): about 0.3 s on 2 cores"), std::string::npos) << s.str();
  fs::remove(log);
  fs::remove_all(out);
}

// Issue 30, seeds: CLI11 read 2⁶⁴ into the unsigned seed as 0 (any larger number as something else): a seed is a
// whole number of 0 … 2⁶⁴ − 1, refused beyond as bad usage naming the flag; 2⁶⁴ − 1 itself is a seed.
TEST(Cli, ASeedBeyond64BitsIsBadUsage) {
  const std::string scene = kDefaultScene.string();
  const auto out = temp_path("cli_seed");
  for (const std::string& cmd : {"synth " + scene + " --teeth 1 --out " + out.string() + "/m.csv",
                                "compensate " + scene + " --out " + out.string()}) {
    for (const std::string seed : {"18446744073709551616", "99999999999999999999999"}) {
      const auto r = run(cmd + " --seed " + seed);
      EXPECT_EQ(r.code, 2) << cmd << ": " << r.err;
      EXPECT_NE(r.err.find("--seed"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("beyond 2⁶⁴ − 1 = 18446744073709551615, the largest seed"), std::string::npos) << r.err;
    }
  }
  EXPECT_FALSE(fs::exists(out));
  const auto r = run("synth " + scene + " --teeth 1 --seed 18446744073709551615 --out " + out.string() + "/m.csv");
  EXPECT_EQ(r.code, 0) << r.err;
  fs::remove_all(out);
}

namespace {
std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }
} // namespace

// Issue 30, errors first: `run` printed its banner ("geartopo run: <scene>") on stderr before a refusal, so the first
// line a user or a script saw was not the error. Every command that fails now prints its error first; what it had said
// before (banner, notes) follows it.
TEST(Cli, ACommandThatFailsPrintsItsErrorFirst) {
  const std::string scene = kDefaultScene.string(), nan = corpus("topology/nan_deviation.csv");
  const auto out = temp_path("cli_errors_first");
  const std::vector<std::string> cases{
      "run " + scene + " --measured " + nan + " --out " + out.string(),
      "report " + scene + " --measured " + nan + " --out " + out.string(),
      "diagnose " + scene + " --measured " + nan + " --out " + out.string(),
      "compare " + scene + " --measured " + nan + " --out " + out.string(),
      "evaluate " + scene + " --traces " + corpus("topology/traces_nan.csv") + " --out " + out.string(),
      "gear " + corpus("scenes/wheel_alias_module.yaml"),
      "simulate " + corpus("scenes/teeth_listed_twice.yaml") + " --out " + out.string(),
      "merge " + corpus("shards/reference/part_1_of_2.csv") + " " + corpus("shards/class_99.csv") + " --out " + out.string(),
  };
  for (const auto& args : cases) {
    const auto r = run(args);
    EXPECT_EQ(r.code, 1) << args << ": " << r.err;
    EXPECT_EQ(first_line(r.err).rfind("geartopo: error: ", 0), 0u) << args << ": " << r.err;
    fs::remove_all(out);
  }
  // The banner is still said, after the error.
  const auto r = run(cases[0]);
  const auto banner = r.err.find("geartopo run: ");
  EXPECT_NE(banner, std::string::npos) << r.err;
  EXPECT_GT(banner, r.err.find("geartopo: error: ")) << r.err;
  fs::remove_all(out);
}

// Issue 30: the scene's measurement.teeth and the --teeth flag refuse a duplicate with the same words.
TEST(Cli, ADuplicateToothIsRefusedInTheSameWordsFromTheSceneAndTheFlag) {
  const auto out = temp_path("cli_teeth_twice");
  const auto flag = run("simulate " + kDefaultScene.string() + " --teeth 1,1 --out " + out.string());
  const auto scene = run("simulate " + corpus("scenes/teeth_listed_twice.yaml") + " --out " + out.string());
  EXPECT_EQ(flag.code, 2) << flag.err;
  EXPECT_EQ(scene.code, 1) << scene.err;
  for (const auto* r : {&flag, &scene}) EXPECT_NE(r->err.find("tooth 1 is listed twice"), std::string::npos) << r->err;
  EXPECT_NE(scene.err.find("teeth_listed_twice.yaml:9:"), std::string::npos) << scene.err;
  fs::remove_all(out);
}

// Issue 30: `merge` refused nothing a shard said (F_α 1e300 µm, a negative F_α, class 99 were merged, exit 0).
TEST(Cli, MergeRefusesAShardThatCompensateCouldNotHaveWritten) {
  const auto out = temp_path("cli_merge");
  const std::string ref = corpus("shards/reference/part_1_of_2.csv");
  for (const auto& [file, where] : std::vector<std::pair<std::string, std::string>>{
           {"value_1e300.csv", "value_1e300.csv:14:"},
           {"negative_total_deviation.csv", "negative_total_deviation.csv:15:"},
           {"class_99.csv", "class_99.csv:14:"},
           // another run's shard: named at its first differing setting, beside the reference's
           {"seed_differs.csv", "seed_differs.csv:3: seed: 8 (" + ref + ":3: 7): not the same run"}}) {
    const auto r = run("merge " + ref + " " + corpus("shards/" + file) + " --out " + out.string());
    EXPECT_EQ(r.code, 1) << file << ": " << r.err;
    EXPECT_NE(r.err.find(where), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out / "prediction.json")) << file;
    fs::remove_all(out);
  }
}

// Issue 31, flags: a numeric flag is finite and in range, a flag that cannot act in the combination given is bad usage
// naming it (it was ignored), and a word flag names the words allowed (CLI11 printed its internal map).
TEST(Cli, FlagsThatWouldDoNothingOrOverflowAreBadUsage) {
  const std::string scene = kDefaultScene.string();
  const auto out = temp_path("cli_flags31");
  const std::string mka = corpus("exports/reference/good.mka");
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases{
      {"compensate " + scene + " --out " + out.string() + " --adaptive-tolerance-um nan",
       {"--adaptive-tolerance-um", "'nan' is not a finite number"}},
      {"compensate " + scene + " --out " + out.string() + " --samples 0 --probe-noise-um 0.3",
       {"--probe-noise-um", "has no effect with --samples 0"}},
      {"compensate " + scene + " --out " + out.string() + " --samples 0 --adaptive-tolerance-um 0.5",
       {"--adaptive-tolerance-um", "has no effect with --samples 0"}},
      {"compensate " + scene + " --out " + out.string() + " --max-samples 500",
       {"--max-samples", "has no effect without --adaptive-tolerance-um"}},
      {"compensate " + scene + " --out " + out.string() + " --samples 200 --adaptive-tolerance-um 0.5",
       {"--samples", "200 has no effect with --adaptive-tolerance-um"}},
      {"run " + scene + " --out " + out.string() + " --samples 0 --probe-noise-um 0.3", {"--probe-noise-um"}},
      {"diagnose " + scene + " --measured " + mka + " --out " + out.string() + " --noise-um 1e-320",
       {"--noise-um", "1e-320 µm is not a probe noise σ: 1e-06 … 1000 µm"}},
      {"plan " + scene + " --measured " + mka + " --noise-um 1e-320", {"--noise-um", "is not a probe noise σ"}},
      {"compare " + scene + " --measured " + mka + " --out " + out.string() + " --noise-um 0", {"--noise-um"}},
      {"compare " + scene + " --measured " + mka + " --out " + out.string() + " --mka-spacing radius",
       {"--mka-spacing: 'radius' is not one of roll-length, diameter"}},
      {"compare " + scene + " --measured " + mka + " --out " + out.string() + " --mka-signs +", {"'+' is not one of raw, din"}},
      // An --mka-… option for a file that is not an export would do nothing (refused before the file is read).
      {"compare " + scene + " --measured " + corpus("topology/huge_deviation.csv") + " --out " + out.string() + " --mka-signs din",
       {"--mka-signs: has no effect: ", "huge_deviation.csv is not a Klingelnberg export"}},
      {"evaluate " + scene + " --traces " + corpus("topology/traces_huge_deviation.csv") + " --out " + out.string() +
           " --mka-direction normal",
       {"--mka-direction"}},
      // run and report read the scene's measurement (a topology CSV here) or --measured's
      {"run " + scene + " --out " + out.string() + " --samples 0 --mka-spacing diameter",
       {"--mka-spacing: has no effect: ", "measured.csv is not a Klingelnberg export"}},
      {"report " + scene + " --measured " + corpus("topology/huge_deviation.csv") + " --out " + out.string() +
           " --samples 0 --mka-signs din",
       {"--mka-signs: has no effect: "}},
  };
  for (const auto& [args, fragments] : cases) {
    const auto r = run(args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    for (const auto& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(r.err.find("->"), std::string::npos) << "CLI11's map in: " << r.err;
    EXPECT_EQ(r.out.find("inf"), std::string::npos) << args << ": " << r.out;
  }
  EXPECT_FALSE(fs::exists(out / "diagnosis.json"));
  fs::remove_all(out);
}

// Issue 31: a UTF-16 export was reported as a topology CSV with a bad header.
TEST(Cli, AUtf16MeasurementIsNamedAsSuch) {
  const auto out = temp_path("cli_utf16");
  for (const std::string file : {"utf16_le_bom.mka", "utf16_no_bom.mka"}) {
    const auto r = run("compare " + kDefaultScene.string() + " --measured " + corpus("exports/" + file) + " --out " + out.string());
    expect_bad_input(r, file);
    EXPECT_NE(r.err.find("UTF-16"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("save it as UTF-8 or latin-1"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("header"), std::string::npos) << r.err;
  }
  fs::remove_all(out);
}

// Issue 31: evaluate --prediction accepted another gear's prediction and hostile values without a word, and said
// "[json.exception.out_of_range.406]" of a 1e400. The prediction is read (and its gear compared) before the traces.
TEST(Cli, EvaluateRefusesAPredictionOfAnotherGearOrWithBadValues) {
  const auto out = temp_path("cli_prediction");
  const std::string evaluate = "evaluate " + kDefaultScene.string() + " --traces " + (out / "none.csv").string() + " --out " +
                               out.string() + " --prediction ";
  const auto other = run(evaluate + corpus("predictions/reference/other_gear.json"));
  expect_bad_input(other, "other_gear.json");
  EXPECT_NE(other.err.find("a prediction of another gear (teeth=36 "), std::string::npos) << other.err;
  EXPECT_NE(other.err.find("is teeth=35 "), std::string::npos) << other.err;
  const auto good = run(evaluate + corpus("predictions/reference/good.json")); // passes the gear, fails at the traces
  EXPECT_EQ(good.code, 1) << good.err;
  EXPECT_NE(good.err.find("none.csv"), std::string::npos) << good.err;
  for (const std::string file : {"value_1e400.json", "duplicate_quantity.json", "class_1_5.json", "coverage_2.json"}) {
    const auto r = run(evaluate + corpus("predictions/" + file));
    expect_bad_input(r, file);
    EXPECT_EQ(r.err.find("json.exception"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(out / "iso1328.json"));
  fs::remove_all(out);
}
