// geartopo tests — every public entry of the libraries that takes teeth, a grid, trace points, a sample count, a noise
// σ, a step or a path refuses an out-of-range value itself, with std::invalid_argument naming the parameter, the
// value and the range (core/limits.hpp), when called directly — bypassing both front ends (issue 43). Hostile values:
// 0, negative, huge, NaN/inf, a tooth twice or beyond z, a grid of 10⁹, an empty path or one holding a NUL. Each must
// be refused at once: not a crash, a hang, an allocation of the value's size or a non-finite result.
#include "geartopo/compensation/compensator.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/core/limits.hpp"
#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/pipeline/pipeline.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/series/series_file.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <string>

namespace library_entries_test { // named: the unity build shares one unit with test_limits.cpp

using namespace geartopo;
using namespace std::string_literals;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

const workbench::Workbench& bench() {
  static const workbench::Workbench wb(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml");
  return wb;
}

/// The message of the std::invalid_argument `f` throws; "no exception" or "another exception: …" otherwise. Every
/// refusal must come before any work: a second at most (a grid of 10⁹ simulated would take hours).
template <typename F>
std::string refusal(F f) {
  const auto start = std::chrono::steady_clock::now();
  std::string out = "no exception";
  try {
    f();
  } catch (const std::invalid_argument& e) {
    out = e.what();
  } catch (const std::exception& e) {
    out = std::string("another exception: ") + e.what();
  }
  if (std::chrono::steady_clock::now() - start > std::chrono::seconds(1)) out += " (after more than a second)";
  return out;
}

/// `message` names `parameter`, shows `value` and says the range `range`.
::testing::AssertionResult names(const std::string& message, const std::string& parameter, const std::string& value,
                                 const std::string& range) {
  for (const auto* part : {&parameter, &value, &range})
    if (message.find(*part) == std::string::npos)
      return ::testing::AssertionFailure() << "'" << *part << "' not in: " << message;
  if (message.find("after more than a second") != std::string::npos) return ::testing::AssertionFailure() << message;
  return ::testing::AssertionSuccess();
}

grinding::SimulationOptions small_simulation() {
  grinding::SimulationOptions so;
  so.teeth = {1};
  return so;
}

TEST(LibraryEntries, SimulateTopologyRefusesTeethGridsAndTracePoints) {
  const auto simulate = [](const grinding::SimulationOptions& so) {
    return refusal([&] { grinding::simulate_topology(bench().setup, bench().process(), so); });
  };
  for (const auto& [teeth, value] : std::vector<std::pair<std::vector<int>, std::string>>{
           {{0}, "0 is not a tooth"}, {{-3}, "-3 is not a tooth"}, {{36}, "36 is not a tooth"},
           {{std::numeric_limits<int>::max()}, "2147483647 is not a tooth"}}) {
    auto so = small_simulation();
    so.teeth = teeth;
    EXPECT_TRUE(names(simulate(so), "simulate_topology: teeth", value, "1 … 35"));
  }
  auto twice = small_simulation();
  twice.teeth = {1, 18, 1};
  EXPECT_TRUE(names(simulate(twice), "simulate_topology: teeth", "tooth 1 is given twice", ""));
  for (const auto& [rows, cols] : std::vector<std::pair<int, int>>{{0, 9}, {1, 9}, {-7, 9}, {7, 1'000'000'000}, {1001, 9}}) {
    auto so = small_simulation();
    so.rows = rows, so.cols = cols;
    EXPECT_TRUE(names(simulate(so), "simulate_topology: rows × cols", fmt::format("{} × {}", rows, cols), "2 … 1000"));
  }
  for (const auto& [p, h] : std::vector<std::pair<int, int>>{{0, 150}, {100, -1}, {1'000'000'000, 150}}) {
    auto so = small_simulation();
    so.profile_points = p, so.helix_points = h;
    EXPECT_TRUE(names(simulate(so), "simulate_topology: profile_points, helix_points", fmt::format("{}, {}", p, h),
                      "2 … 100000"));
  }
  for (const auto& [r, c] : std::vector<std::pair<int, int>>{{-1, -1}, {5, 0}}) {
    auto so = small_simulation();
    so.dense_rows = r, so.dense_cols = c;
    EXPECT_TRUE(names(simulate(so), "simulate_topology: dense_rows × dense_cols", fmt::format("{} × {}", r, c),
                      "both 0 (none) or both ≥ 1"));
  }
  auto dense = small_simulation();
  dense.dense_rows = dense.dense_cols = 1'000'000'000; // 10¹⁸ points: refused before any allocation
  EXPECT_TRUE(names(simulate(dense), "simulate_topology: points", "1000000000000000313 per flank",
                    "4000000 per flank, 100000000 in all"));
}

TEST(LibraryEntries, SynthesizeRefusesNoiseTeethAndGrids) {
  for (double noise : {-1.0, -1e-300, 1000.5, 1e300, kNaN, kInf, -kInf}) {
    diagnosis::SynthOptions o;
    o.noise_um = noise;
    EXPECT_TRUE(names(refusal([&] { diagnosis::synthesize(bench().setup, bench().process(), o); }),
                      "synthesize: noise_um", fmt::format("{}", noise), "0 (none) … 1000 µm"));
    EXPECT_TRUE(names(refusal([&] { diagnosis::synthesize_traces(bench().setup, bench().process(), o, 100, 150); }),
                      "synthesize_traces: noise_um", fmt::format("{}", noise), "0 (none) … 1000 µm"));
  }
  diagnosis::SynthOptions o;
  o.teeth = {18, 18};
  EXPECT_TRUE(names(refusal([&] { diagnosis::synthesize(bench().setup, bench().process(), o); }), "teeth",
                    "tooth 18 is given twice", ""));
  o.teeth = {1};
  o.rows = 1'000'000'000;
  EXPECT_TRUE(names(refusal([&] { diagnosis::synthesize(bench().setup, bench().process(), o); }), "rows × cols",
                    "1000000000 × 9", "2 … 1000"));
  o.rows = 7;
  EXPECT_TRUE(names(refusal([&] { diagnosis::synthesize_traces(bench().setup, bench().process(), o, 0, 150); }),
                    "profile_points, helix_points", "0, 150", "2 … 100000"));
  std::vector<grinding::FlankTopology> topo(1);
  EXPECT_TRUE(names(refusal([&] { diagnosis::add_probe_noise(topo, kNaN, [] { return 0.0; }); }),
                    "add_probe_noise: noise_um", "nan", "0 (none) … 1000 µm"));
}

const std::vector<measurement::MeasuredPoint>& measured() {
  static const auto pts = [] {
    diagnosis::SynthOptions o;
    o.teeth = {1, 18};
    return measurement::measured_points(diagnosis::synthesize(bench().setup, bench().process(), o),
                                        bench().setup.geometry(), "synthetic");
  }();
  return pts;
}

TEST(LibraryEntries, CompareAndDiagnoseRefuseANoiseTheyWouldDivideBy) {
  for (double noise : {-1.0, 1e-320, 1e-158, 5e-7, 1000.5, kNaN, kInf}) {
    EXPECT_TRUE(names(refusal([&] { diagnosis::compare(bench().setup, bench().process(), measured(), noise); }),
                      "compare: noise_um", fmt::format("{}", noise), "0 (estimated) or 1e-06 … 1000 µm"));
    diagnosis::DiagnoseOptions o;
    o.noise_um = noise;
    EXPECT_TRUE(names(refusal([&] {
                        diagnosis::diagnose(bench().setup, bench().process(), measured(), bench().effect_types(), o);
                      }),
                      "diagnose: option noise_um", fmt::format("{}", noise), "0 (estimated) or 1e-06 … 1000 µm"));
  }
}

TEST(LibraryEntries, TheMonteCarloRefusesSamplesAndNoise) {
  const compensation::CorrectionTable none({}); // refused before the table is looked at
  for (long long samples : {0LL, -5LL, limits::kMaxSamples + 1, 1'000'000'000LL, std::numeric_limits<long long>::max()}) {
    pipeline::MonteCarloOptions o;
    o.samples = samples;
    EXPECT_TRUE(names(refusal([&] { pipeline::run_monte_carlo(bench(), none, o); }), "samples",
                      fmt::format("{}", samples), "1 … 1000000"));
  }
  for (double noise : {-1.0, kNaN, kInf, 1e9}) {
    pipeline::MonteCarloOptions o;
    o.samples = 10;
    o.probe_noise_um = noise;
    EXPECT_TRUE(names(refusal([&] { pipeline::run_monte_carlo(bench(), none, o); }), "run_monte_carlo: probe_noise_um",
                      fmt::format("{}", noise), "0 (none) … 1000 µm"));
  }
  pipeline::MonteCarloOptions o;
  o.adaptive_tolerance_um = kNaN;
  EXPECT_TRUE(names(refusal([&] { pipeline::run_monte_carlo(bench(), none, o); }),
                    "run_monte_carlo: adaptive_tolerance_um", "nan", "0 (off) or a finite tolerance > 0 µm"));
}

TEST(LibraryEntries, CompensationRefusesAStepItCouldNotSampleWith) {
  // 0 and NaN made the path's sample count undefined behaviour (ceil(len / 0) cast to int), 1e-9 mm billions of poses.
  for (double step : {0.0, -2.0, 1e-9, 0.049, 50.5, kNaN, kInf}) {
    compensation::CompensationOptions co;
    co.step_mm = step;
    EXPECT_TRUE(names(refusal([&] {
                        compensation::compute_corrections(bench().setup, bench().process(),
                                                          {bench().machine, bench().scene.machine.datum_face_z_mm}, co);
                      }),
                      "compute_corrections: step_mm", fmt::format("{}", step), "0.05 … 50 mm"));
  }
}

TEST(LibraryEntries, ThePipelineRefusesWhatItIsGivenBeforeAnyWork) {
  const auto run = [](const pipeline::PipelineOptions& o) { return refusal([&] { pipeline::run_pipeline(bench(), o); }); };
  pipeline::PipelineOptions o;
  o.teeth = {1, 36};
  EXPECT_TRUE(names(run(o), "run_pipeline: teeth", "36 is not a tooth", "1 … 35"));
  o.teeth = {2, 2};
  EXPECT_TRUE(names(run(o), "run_pipeline: teeth", "tooth 2 is given twice", ""));
  o.teeth = {1};
  o.noise_um = 1e-158;
  EXPECT_TRUE(names(run(o), "run_pipeline: noise_um", "1e-158", "0 (estimated) or 1e-06 … 1000 µm"));
  o.noise_um = 0.0;
  o.measured_file = "scenes/demo/measured.csv\0.bak"s;
  EXPECT_TRUE(names(run(o), "run_pipeline: measured_file", "NUL character at 24", "no file is named so"));
  o.measured_file.clear();
  o.prediction.emplace();
  o.prediction->samples = 1'000'000'000;
  EXPECT_TRUE(names(run(o), "run_pipeline: prediction samples", "1000000000", "1 … 1000000"));
  o.prediction->samples = 10;
  o.prediction->probe_noise_um = -kInf;
  EXPECT_TRUE(names(run(o), "run_pipeline: probe_noise_um", "-inf", "0 (none) … 1000 µm"));
  o.prediction.reset();
  o.step_mm = kNaN;
  EXPECT_TRUE(names(run(o), "step_mm", "nan", "0.05 … 50 mm"));
}

TEST(LibraryEntries, EveryReaderRefusesAPathWithANulAndAnEmptyOne) {
  // "measured.csv\0.bak" would be cut at the NUL by stat() and open() and read measured.csv.
  const std::string dir = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/";
  const std::string nul_measured = dir + "demo/measured.csv\0.bak"s;
  const std::string nul_scene = dir + "skmc1200w-mn14-z35.yaml\0x"s;
  const auto nul_refused = [](const std::string& message) {
    return names(message, "", "NUL character", "no file is named so");
  };
  EXPECT_TRUE(nul_refused(refusal([&] { measurement::read_any_measurement(nul_measured, bench().setup); })));
  EXPECT_TRUE(nul_refused(refusal([&] { measurement::read_any_traces(nul_measured, bench().setup); })));
  EXPECT_TRUE(nul_refused(refusal([&] { measurement::read_measurement(nul_measured, bench().setup.geometry()); })));
  EXPECT_TRUE(nul_refused(refusal([&] { scene::load_scene(nul_scene); })));
  EXPECT_TRUE(nul_refused(refusal([&] { series::series_scene(nul_scene); })));
  EXPECT_TRUE(nul_refused(refusal([&] { series::load_series(nul_scene, 1.0); })));
  // An empty path: the readers' located error (an InputError), as before — clear, naming what was expected.
  for (const auto& message : {refusal([&] { measurement::read_any_measurement("", bench().setup); }),
                              refusal([&] { scene::load_scene(""); }), refusal([&] { series::load_series("", 1.0); })})
    EXPECT_NE(message.find("another exception: \"\": an empty name is not a"), std::string::npos) << message;
}

} // namespace library_entries_test
