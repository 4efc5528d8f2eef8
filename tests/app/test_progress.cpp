// Progress of long work (issues 17 and 18): the library's progress callbacks — Monte Carlo samples, diagnosis
// candidates — are called once per unit of work with counts that follow from the options and the documented rules,
// change nothing in the results, and a callback that throws stops the Monte Carlo run; the command line shows
// progress only on a terminal (a pseudo-terminal made by util-linux `script`) and never with --quiet or in a pipe, and
// refuses a prediction whose estimate exceeds --max-time-s before it writes anything.
#include "geartopo/compensation/compensator.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/scene/scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

using namespace geartopo;

namespace {

// A small helical gear (fast to simulate) with constant machine errors, two teeth simulated.
std::string progress_scene_text(const std::string& effects) {
  return "gear:\n"
         "  normal_module_mm: 4\n"
         "  teeth: 20\n"
         "  normal_pressure_angle_deg: 20\n"
         "  helix_angle_deg: 20\n"
         "  profile_shift: 0\n"
         "  face_width_mm: 30\n"
         "machine:\n"
         "  datum_face_z_mm: 300\n"
         "  constants: {S_xz_urad: 30, E_XOC_um: 5, delta_xx_um: 4, epsilon_zx_urad: 40, E_YOC_um: 6}\n"
         "wheel: {outer_diameter_mm: 300}\n"
         "measurement: {rows: 5, cols: 5, profile_points: 15, helix_points: 15, teeth: [1, 11]}\n" +
         effects;
}

compensation::CorrectionTable corrections_of(const workbench::Workbench& wb) {
  compensation::CompensationOptions co;
  co.step_mm = 2.0;
  return compensation::compute_corrections(wb.setup, wb.process(), {wb.machine, wb.scene.machine.datum_face_z_mm}, co);
}

struct CallLog {
  std::mutex mutex;
  std::vector<std::pair<long long, long long>> calls; // (done, total) in the order received
  void operator()(long long done, long long total) {
    const std::lock_guard lock(mutex);
    calls.emplace_back(done, total);
  }
};

struct CliRun {
  int code;
  std::string out, err;
};

std::string slurp_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The program with stdout and stderr each into a file (not a terminal).
CliRun run_in_pipe(const std::string& args) {
  static int calls = 0;
  const auto base = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_progress_" + std::to_string(calls++));
  const std::string cmd = std::string(GEARTOPO_BINARY) + " " + args + " >" + base.string() + ".out 2>" + base.string() + ".err";
  const int status = std::system(cmd.c_str());
  CliRun r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp_file(base.string() + ".out"), slurp_file(base.string() + ".err")};
  std::filesystem::remove(base.string() + ".out");
  std::filesystem::remove(base.string() + ".err");
  return r;
}

bool script_present() { return std::system("command -v script > /dev/null 2>&1") == 0; }

/// The program on a pseudo-terminal (`script -q -e -c`): stdout and stderr both reach the terminal, whose transcript
/// is returned as `out`.
CliRun run_on_terminal(const std::string& args) {
  static int calls = 0;
  const auto log = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_pty_" + std::to_string(calls++));
  const std::string cmd = "script -q -e -c \"" + std::string(GEARTOPO_BINARY) + " " + args + "\" " + log.string() + " > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  CliRun r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp_file(log), ""};
  std::filesystem::remove(log);
  return r;
}

/// The small scene as a file, for the command line.
std::string progress_scene_file() {
  const auto p = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_progress_scene.yaml");
  std::ofstream(p) << progress_scene_text("");
  return p.string();
}

/// Every line of a command's stderr is a warning: no progress, estimate or note.
bool only_warnings(const std::string& err) {
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("geartopo: warning: ", 0) != 0) return false;
  return true;
}

} // namespace

// Every sample is told once: the done counts are 1..M (each once, in any order across threads), the total is M; the
// samples are those of a run without the callback, value for value.
TEST(ProgressMonteCarlo, OnSampleDoneCountsEverySampleOnceAndChangesNothing) {
  const workbench::Workbench wb(scene::parse_scene(progress_scene_text(""), "mem"));
  const auto table = corrections_of(wb);
  pipeline::MonteCarloOptions o;
  o.samples = 6;
  o.threads = 2;
  const auto plain = pipeline::run_monte_carlo(wb, table, o);
  CallLog log;
  o.on_sample_done = std::ref(log);
  const auto told = pipeline::run_monte_carlo(wb, table, o);
  ASSERT_EQ(log.calls.size(), 6u);
  std::vector<long long> done;
  for (const auto& [d, t] : log.calls) {
    EXPECT_EQ(t, 6);
    done.push_back(d);
  }
  std::sort(done.begin(), done.end());
  EXPECT_EQ(done, (std::vector<long long>{1, 2, 3, 4, 5, 6}));
  ASSERT_EQ(told.samples.size(), plain.samples.size());
  for (size_t k = 0; k < plain.samples.size(); ++k) {
    EXPECT_EQ(told.samples[k].before, plain.samples[k].before) << k;
    EXPECT_EQ(told.samples[k].after, plain.samples[k].after) << k;
  }
}

// The total is the shard's samples (docs: shard_range), not all of them.
TEST(ProgressMonteCarlo, TotalIsTheShardsSamples) {
  const workbench::Workbench wb(scene::parse_scene(progress_scene_text(""), "mem"));
  pipeline::MonteCarloOptions o;
  o.samples = 5;
  o.shard = 2;
  o.shards = 2; // samples 2, 3, 4: ⌊5·1/2⌋ = 2 to ⌊5·2/2⌋ = 5
  o.threads = 1;
  CallLog log;
  o.on_sample_done = std::ref(log);
  pipeline::run_monte_carlo(wb, corrections_of(wb), o);
  ASSERT_EQ(log.calls.size(), 3u);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(log.calls[i], (std::pair<long long, long long>(static_cast<long long>(i) + 1, 3)));
}

// An adaptive run counts on across its batches, towards its limit (the stop is not known before): the done counts are
// 1..(samples it stopped at), each once, and the total is --max-samples.
TEST(ProgressMonteCarlo, AnAdaptiveRunCountsAcrossItsBatchesTowardsItsLimit) {
  const workbench::Workbench wb(scene::parse_scene(progress_scene_text(""), "mem"));
  pipeline::MonteCarloOptions o;
  o.adaptive_tolerance_um = 1e3; // stable after the first two batches
  o.adaptive_batch = 3;
  o.adaptive_max_samples = 12;
  o.threads = 2;
  CallLog log;
  o.on_sample_done = std::ref(log);
  const auto run = pipeline::run_monte_carlo(wb, corrections_of(wb), o);
  ASSERT_EQ(run.samples_total, 6); // two batches of 3: the least an adaptive run does
  ASSERT_EQ(log.calls.size(), 6u);
  std::vector<long long> done;
  for (const auto& [d, t] : log.calls) {
    EXPECT_EQ(t, 12);
    done.push_back(d);
  }
  std::sort(done.begin(), done.end());
  EXPECT_EQ(done, (std::vector<long long>{1, 2, 3, 4, 5, 6}));
}

// A callback that throws (a work estimate beyond its limit) stops the run: on one thread no sample after the first
// starts, and run_monte_carlo passes the exception on.
TEST(ProgressMonteCarlo, AThrowingCallbackStopsTheRun) {
  const workbench::Workbench wb(scene::parse_scene(progress_scene_text(""), "mem"));
  pipeline::MonteCarloOptions o;
  o.samples = 20;
  o.threads = 1;
  int calls = 0;
  o.on_sample_done = [&calls](long long, long long) {
    ++calls;
    throw std::runtime_error("too long");
  };
  EXPECT_THROW(pipeline::run_monte_carlo(wb, corrections_of(wb), o), std::runtime_error);
  EXPECT_EQ(calls, 1);
}

// The diagnosis tells every candidate fit: first the single effects asked for, then — when the best one is significant —
// every pair among the favoured ones (ΔBIC below −threshold, at most pair_candidates of them; DiagnoseOptions). The
// counts run 1, 2, … without a gap, the last total is the number of fits, and the diagnosis is the one without callback.
TEST(ProgressDiagnose, OnCandidateFittedCountsSinglesThenPairs) {
  const workbench::Workbench model(scene::parse_scene(progress_scene_text(""), "model"));
  const workbench::Workbench truth(scene::parse_scene(
      progress_scene_text("effects:\n  - {type: thermal_drift, x_growth_um: 20, time_constant_s: 120}\n"), "truth"));
  diagnosis::SynthOptions so;
  so.teeth = {1, 6, 11, 16};
  so.rows = 5;
  so.cols = 5;
  so.noise_um = 0.3;
  const auto pts = measurement::measured_points(diagnosis::synthesize(truth.setup, truth.process(), so),
                                                model.setup.geometry(), "synth");
  diagnosis::DiagnoseOptions o;
  o.noise_um = so.noise_um;
  o.candidates = {"thermal_drift", "wheel_wear", "eccentricity"};
  const auto plain = diagnosis::diagnose(model.setup, model.process(), pts, model.effect_types(), o);
  CallLog log;
  o.on_candidate_fitted = std::ref(log);
  const auto told = diagnosis::diagnose(model.setup, model.process(), pts, model.effect_types(), o);

  long long favoured = 0;
  for (const auto& c : plain.ranked) favoured += c.delta_bic < -o.bic_threshold ? 1 : 0;
  const long long top = std::min<long long>(favoured, static_cast<long long>(o.pair_candidates));
  const long long pairs = !plain.ranked.empty() && plain.ranked.front().significant ? top * (top - 1) / 2 : 0;
  ASSERT_GT(pairs, 0) << "the drift must make more than one candidate significant, so that the pairs are told too: "
                      << plain.verdict;
  const long long fits = 3 + pairs;
  ASSERT_EQ(static_cast<long long>(log.calls.size()), fits) << plain.verdict;
  for (size_t i = 0; i < log.calls.size(); ++i) {
    EXPECT_EQ(log.calls[i].first, static_cast<long long>(i) + 1);
    EXPECT_EQ(log.calls[i].second, i < 3 ? 3 : fits); // the pairs are known once the singles are ranked
  }
  EXPECT_EQ(told.verdict, plain.verdict);
  ASSERT_EQ(told.ranked.size(), plain.ranked.size());
  for (size_t i = 0; i < plain.ranked.size(); ++i) EXPECT_EQ(told.ranked[i].delta_bic, plain.ranked[i].delta_bic);
}

// Scripts and logs (stderr a file) see no progress line, with or without --quiet; on a terminal the prediction's
// progress and its work estimate appear, and --quiet silences them.
TEST(ProgressCli, OnlyOnATerminalAndNeverWithQuiet) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_progress_cli");
  const std::string args = "compensate " + progress_scene_file() + " --samples 2 --out " + dir.string();
  const CliRun piped = run_in_pipe(args);
  ASSERT_EQ(piped.code, 0) << piped.err;
  EXPECT_EQ(piped.err.find('\r'), std::string::npos) << piped.err;
  EXPECT_EQ(piped.err.find("Monte Carlo"), std::string::npos) << piped.err;
  const CliRun piped_quiet = run_in_pipe(args + " --quiet");
  ASSERT_EQ(piped_quiet.code, 0) << piped_quiet.err;
  EXPECT_TRUE(only_warnings(piped_quiet.err)) << piped_quiet.err;
  if (!script_present()) GTEST_SKIP() << "util-linux 'script' is not installed: no pseudo-terminal for the terminal case";
  const CliRun tty = run_on_terminal(args);
  ASSERT_EQ(tty.code, 0) << tty.out;
  EXPECT_NE(tty.out.find("geartopo: Monte Carlo: 2 samples at"), std::string::npos) << tty.out;
  EXPECT_NE(tty.out.find("predict (Monte Carlo) 2/2 samples"), std::string::npos) << tty.out;
  const CliRun tty_quiet = run_on_terminal(args + " --quiet");
  ASSERT_EQ(tty_quiet.code, 0) << tty_quiet.out;
  EXPECT_EQ(tty_quiet.out.find("Monte Carlo:"), std::string::npos) << tty_quiet.out;
  EXPECT_EQ(tty_quiet.out.find("samples,"), std::string::npos) << tty_quiet.out;
  EXPECT_EQ(tty_quiet.out.find('\r' + std::string("geartopo:")), std::string::npos) << tty_quiet.out;
  std::filesystem::remove_all(dir);
}

// A prediction whose estimate (first sample's time × ⌈samples / threads⌉) exceeds --max-time-s is refused as bad
// usage of --samples, naming the estimate and the limit, before any output file is written.
TEST(ProgressCli, APredictionBeyondTheTimeLimitIsRefusedBeforeAnyFile) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_progress_refused");
  const CliRun r = run_in_pipe("compensate " + progress_scene_file() + " --samples 3 --max-time-s 0.001 --out " + dir.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--samples"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("3 samples at"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("beyond the limit of 0.001 s (--max-time-s)"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "corrections.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "iso1328.json"));
  std::filesystem::remove_all(dir);
}

// Long work says its cost up front (issue 25): a simulation whose measured estimate (the first flank's time ×
// ⌈flanks / threads⌉) exceeds --max-time-s is refused as bad usage of --max-time-s, naming the stage, the estimate and
// the limit, before any output file is written — for simulate, and for run through its first simulation stage.
TEST(ProgressCli, ASimulationBeyondTheTimeLimitIsRefusedBeforeAnyFile) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_simulate_refused");
  // A 60×60 grid: 3 655 points per flank take ≈ 14 ms at the documented 260 k points/s, far beyond the 1 ms limit
  // even on a much faster machine, so the first stage is the one refused.
  std::string text = progress_scene_text("");
  const std::string small_grid = "rows: 5, cols: 5";
  text.replace(text.find(small_grid), small_grid.size(), "rows: 60, cols: 60");
  const auto scene = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_refused_scene.yaml");
  std::ofstream(scene) << text;
  const CliRun sim = run_in_pipe("simulate " + scene.string() + " --max-time-s 0.001 --out " + dir.string());
  EXPECT_EQ(sim.code, 2) << sim.err;
  EXPECT_NE(sim.err.find("simulate 4 flanks at"), std::string::npos) << sim.err; // teeth 1 and 11, both flanks
  EXPECT_NE(sim.err.find("beyond the limit of 0.001 s (--max-time-s)"), std::string::npos) << sim.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "topology.csv"));
  const CliRun run = run_in_pipe("run " + scene.string() + " --samples 0 --max-time-s 0.001 --out " + dir.string());
  EXPECT_EQ(run.code, 2) << run.err;
  EXPECT_NE(run.err.find("simulate 4 flanks at"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "index.html"));
  EXPECT_FALSE(std::filesystem::exists(dir / "iso1328.json"));
  std::filesystem::remove_all(dir);
  std::filesystem::remove(scene);
}

// A large simulation prints its a-priori estimate (points at the documented rate) even into a log, where nothing
// else of the progress appears; a small one prints nothing, and --quiet silences it.
TEST(ProgressCli, ALargeSimulationSaysItsCostEvenInALog) {
  const auto dir = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_simulate_estimate");
  // 2 flanks × (710 × 710 dense + 25 grid + 30 trace points) = 1 008 310 points ≥ kEstimateFromPoints (1 000 000).
  const std::string large = "simulate " + progress_scene_file() + " --teeth 1 --dense 710x710 --method linear --out " + dir.string();
  const CliRun told = run_in_pipe(large);
  ASSERT_EQ(told.code, 0) << told.err;
  EXPECT_NE(told.err.find("geartopo: 1008310 points on 2 flanks (linear): about"), std::string::npos) << told.err;
  EXPECT_EQ(told.err.find('\r'), std::string::npos) << told.err;
  const CliRun quiet = run_in_pipe(large + " --quiet");
  ASSERT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find("points on"), std::string::npos) << quiet.err;
  const CliRun small = run_in_pipe("simulate " + progress_scene_file() + " --out " + dir.string());
  ASSERT_EQ(small.code, 0) << small.err;
  EXPECT_EQ(small.err.find("points on"), std::string::npos) << small.err;
  std::filesystem::remove_all(dir);
}
