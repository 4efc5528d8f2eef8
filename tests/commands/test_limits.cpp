// geartopo tests — the bounds both front ends enforce live in the commands library, and the libraries below refuse
// what would overflow them: the CLI's refused values given to the library API directly (issue 43).
#include "geartopo/commands/limits.hpp"
#include "geartopo/commands/measured.hpp"
#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/files/input_file.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace {

using namespace geartopo;

const workbench::Workbench& bench() {
  static const workbench::Workbench wb(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml");
  return wb;
}

const std::vector<measurement::MeasuredPoint>& measured() {
  static const auto pts = [] {
    diagnosis::SynthOptions o;
    o.teeth = {1, 18};
    o.noise_um = 0.5;
    return measurement::measured_points(diagnosis::synthesize(bench().setup, bench().process(), o),
                                        bench().setup.geometry(), "synthetic");
  }();
  return pts;
}

/// The message of the ArgumentError `f` throws ("" when it throws none, or another exception).
template <typename F>
std::string refusal(F f) {
  try {
    f();
  } catch (const commands::ArgumentError& e) {
    return e.what();
  } catch (...) {
    return "another exception";
  }
  return "";
}

const double kHostileNoise[] = {-1.0, 1e-320, 1e-158, 5e-7, 1000.5, std::numeric_limits<double>::quiet_NaN(),
                                std::numeric_limits<double>::infinity()};

TEST(Limits, EveryRefusedNoiseNamesItsArgument) {
  for (double v : kHostileNoise) EXPECT_EQ(refusal([&] { commands::check_noise_um(v, "noise_um"); }).rfind("noise_um: ", 0), 0u) << v;
  EXPECT_EQ(refusal([] { commands::check_noise_um(0.0, "noise_um"); }), "");      // estimated
  EXPECT_EQ(refusal([] { commands::check_noise_um(1e-6, "--noise-um"); }), "");   // the bounds themselves
  EXPECT_EQ(refusal([] { commands::check_noise_um(1000.0, "--noise-um"); }), "");
  EXPECT_NE(refusal([] { commands::check_noise_um(1e-9, "--noise-um"); }).find("--noise-um: 1e-09 µm is not a probe noise"),
            std::string::npos);
}

TEST(Limits, TheLibrariesRefuseANoiseTheyWouldOverflowOn) {
  // Given to the library API directly, bypassing both front ends: a clear refusal, never a crash, an unrelated
  // message or an infinite χ² (1e-158 µm crashed compare's tooth trends; below 1e-170 diagnose's χ² was inf).
  for (double v : kHostileNoise) {
    diagnosis::DiagnoseOptions o;
    o.noise_um = v;
    EXPECT_THROW(diagnosis::diagnose(bench().setup, bench().process(), measured(), bench().effect_types(), o),
                 std::invalid_argument)
        << v;
    EXPECT_THROW(diagnosis::compare(bench().setup, bench().process(), measured(), v), std::invalid_argument) << v;
  }
}

TEST(Limits, TheCommandsCheckBeforeTheyWork) {
  const std::string text = input::read_input_file(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml",
                                                  input::kMaxSceneBytes, "scene file");
  const commands::SceneInput scene{bench(), "skmc1200w-mn14-z35.yaml", text, GEARTOPO_SOURCE_DIR "/scenes"};
  const commands::MeasuredInput m{measured(), "synthetic", {}};
  commands::DiagnoseRequest r;
  r.noise_um = 1e-158;
  EXPECT_EQ(refusal([&] { commands::diagnose(scene, m, r, "."); }).rfind("noise_um: ", 0), 0u);
  EXPECT_EQ(refusal([&] { commands::plan(scene, m, r, {"--noise-um", "--candidates"}); }).rfind("--noise-um: ", 0), 0u);
  EXPECT_EQ(refusal([&] { commands::compare(scene, m, -1.0); }).rfind("noise_um: ", 0), 0u);
  r.noise_um = 0.5;
  r.candidates = {"thermal_drift", "wobble"};
  EXPECT_NE(refusal([&] { commands::diagnose(scene, m, r, "."); }).find("candidates: 'wobble' is not an effect of the library"),
            std::string::npos);
}

TEST(Limits, PathsSamplesGridsAndTeeth) {
  EXPECT_NE(refusal([] { commands::check_path(std::string("m.csv\0.bak", 10), "measured"); }).find("NUL character at 5 ('m.csv'"),
            std::string::npos);
  EXPECT_NE(refusal([] { commands::check_path("", "--out"); }).find("--out: an empty path"), std::string::npos);
  EXPECT_EQ(refusal([] { commands::check_path("out/run", "--out"); }), "");
  EXPECT_NE(refusal([] { commands::check_samples(-1, "samples"); }), "");
  EXPECT_NE(refusal([] { commands::check_samples(1'000'000'000, "samples"); }).find("0 (nominal only) … 1000000"),
            std::string::npos);
  EXPECT_EQ(refusal([] { commands::check_samples(1000, "samples"); }), "");
  EXPECT_NE(refusal([] { commands::check_grid(2147483648LL, 2, "dense"); }).find("dense: 2147483648 × 2 is not a grid"),
            std::string::npos);
  EXPECT_NE(refusal([] { commands::check_grid(0, 5, "dense"); }), "");
  EXPECT_NE(refusal([] { commands::check_teeth({1, 36}, 35, "teeth"); }).find("36 is not a tooth of 1 … 35"), std::string::npos);
  EXPECT_NE(refusal([] { commands::check_teeth({1, 1}, 35, "teeth"); }).find("tooth 1 is given twice"), std::string::npos);
  EXPECT_NE(refusal([] { commands::check_synthetic_noise_um(-0.1, "noise_um"); }), "");
  EXPECT_EQ(refusal([] { commands::check_synthetic_noise_um(0.0, "noise_um"); }), "");
}

} // namespace
