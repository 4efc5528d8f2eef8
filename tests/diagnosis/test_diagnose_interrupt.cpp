// Ctrl-C reaches diagnose's set-up (DiagnoseOptions::keep_going). Before the first candidate's fit diagnose computes,
// over every measured point, the model's exact prediction, one first-order prediction per axis with stroke scatter
// (stroke_sensitivity) and the contact state the fits reuse (EffectContribution): on 10⁶ points each takes seconds,
// so each must check within its loop, not only between the stages (the Python test of a stop within a second is
// python/tests/test_ctrl_c.py; this one counts the checks, which does not depend on the machine's speed).
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/workbench/workbench.hpp"

#include "flank_points.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <random>
#include <stdexcept>

using namespace geartopo;

namespace {

struct Stop : std::runtime_error {
  Stop() : std::runtime_error("stopped by the test's keep_going") {}
};

const workbench::Workbench& interrupt_scene() {
  static const workbench::Workbench b(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml");
  return b;
}

// n points anywhere on the active flanks of every tooth, deviation = white noise of 0.3 µm.
std::vector<measurement::MeasuredPoint> noise_points(const gears::GearGeometry& g, int n) {
  auto pts = geartopo::test::random_flank_points(g, n, 7);
  std::mt19937_64 rng(8);
  std::normal_distribution<double> noise(0.0, 0.3);
  for (auto& p : pts) p.deviation_um = noise(rng);
  return pts;
}

diagnosis::DiagnoseOptions scatter_options() {
  diagnosis::DiagnoseOptions o;
  o.threads = 2;
  o.stroke_repeatability_sd << 1e-3, 1e-3, 1e-3, 1e-6, 1e-6; // X, Y, Z mm; A, C rad: six predictions in the set-up
  o.candidates = {"wheel_runout"};
  return o;
}

} // namespace

// The checks before the first fit: ≥ one per 4096 points of each of the 7 predictions (exact, linear base, 5 axes) and
// one per 1024 points of the contact states. Between the stages alone, as before, they were 6 whatever n.
TEST(DiagnoseInterrupt, TheSetUpChecksWithinEachStageLoop) {
  const auto& wb = interrupt_scene();
  constexpr int n = 3 * 4096;
  const auto pts = noise_points(wb.setup.geometry(), n);
  diagnosis::DiagnoseOptions o = scatter_options();
  std::atomic<long long> calls{0}; // keep_going runs on the work's threads
  long long calls_before_first_fit = -1;
  o.keep_going = [&calls] { ++calls; };
  o.on_candidate_fitted = [&](long long, long long) {
    if (calls_before_first_fit < 0) calls_before_first_fit = calls;
  };
  diagnosis::diagnose(wb.setup, wb.diagnosis_model(), pts, wb.effect_types(), o);
  EXPECT_GE(calls_before_first_fit, 7 * (n / 4096) + n / 1024);
}

// A stop anywhere in the set-up ends the diagnosis with the caller's exception: no fit is reported, nothing is caught.
TEST(DiagnoseInterrupt, AStopAtAnyCheckOfTheSetUpEndsTheDiagnosis) {
  const auto& wb = interrupt_scene();
  const auto pts = noise_points(wb.setup.geometry(), 2 * 4096);
  for (const long long stop_at : {1LL, 2LL, 5LL, 9LL, 14LL, 20LL}) {
    diagnosis::DiagnoseOptions o = scatter_options();
    std::atomic<long long> calls{0};
    bool fitted = false;
    o.keep_going = [&calls, stop_at] {
      if (++calls == stop_at) throw Stop{};
    };
    o.on_candidate_fitted = [&fitted](long long, long long) { fitted = true; };
    EXPECT_THROW(diagnosis::diagnose(wb.setup, wb.diagnosis_model(), pts, wb.effect_types(), o), Stop) << stop_at;
    EXPECT_FALSE(fitted) << "stopped at check " << stop_at;
  }
}
