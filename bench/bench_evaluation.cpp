// ISO 1328-1 evaluation speed on a simulated gear: the default scene simulated once (exact, all 35 teeth, the scene's
// 100-point profile and 150-point helix traces), then
//   EvaluateGear  — evaluation::evaluate_gear on all 70 flanks with pitch and runout, the measurement built from the
//                   topology exactly as the app does (workbench::gear_measurement);
//   EvaluateTrace — evaluation::evaluate_trace on the 140 traces (70 profile + 70 helix).
// Counter `points`: trace points evaluated per second.
#include "bench_scene.hpp"

#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/evaluation/gear_evaluation.hpp"
#include "geartopo/evaluation/trace.hpp"
#include "geartopo/grinding/topology.hpp"

#include <benchmark/benchmark.h>

using namespace geartopo;

namespace {

const std::vector<grinding::FlankTopology>& simulated_gear() {
  static const auto topo = [] {
    const auto& b = bench::default_scene();
    grinding::SimulationOptions o;
    o.profile_points = b.scene.grid.profile_points;
    o.helix_points = b.scene.grid.helix_points;
    return grinding::simulate_topology(b.setup, b.process(), o);
  }();
  return topo;
}

double trace_points(const evaluation::GearMeasurement& m) {
  double n = 0.0;
  for (const auto& f : m.flanks) n += static_cast<double>(f.profile.position_mm.size() + f.helix.position_mm.size());
  return n;
}

void BM_EvaluateGear(benchmark::State& state) {
  const auto& b = bench::default_scene();
  const auto& g = b.setup.geometry();
  const evaluation::GearParameters p{g.teeth(), g.reference_diameter_mm(), g.spec().normal_module_mm,
                                     g.spec().face_width_mm, g.spec().helix_angle_rad};
  const auto m = workbench::gear_measurement(g, b.setup.ranges(), simulated_gear());
  for (auto _ : state) benchmark::DoNotOptimize(evaluation::evaluate_gear(m, p));
  state.counters["points"] = benchmark::Counter(trace_points(m) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["flanks"] = static_cast<double>(m.flanks.size());
}
BENCHMARK(BM_EvaluateGear)->Name("EvaluateGear/70flanks+pitch+runout")->Unit(benchmark::kMillisecond);

// Including the conversion from topology to measurement (what app::evaluate_iso does).
void BM_EvaluateIso(benchmark::State& state) {
  const auto& b = bench::default_scene();
  const auto& g = b.setup.geometry();
  const evaluation::GearParameters p{g.teeth(), g.reference_diameter_mm(), g.spec().normal_module_mm,
                                     g.spec().face_width_mm, g.spec().helix_angle_rad};
  const auto& topo = simulated_gear();
  for (auto _ : state) benchmark::DoNotOptimize(evaluation::evaluate_gear(workbench::gear_measurement(g, b.setup.ranges(), topo), p));
  state.counters["points"] = benchmark::Counter(trace_points(workbench::gear_measurement(g, b.setup.ranges(), topo)) *
                                                    static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
BENCHMARK(BM_EvaluateIso)->Name("EvaluateGear/70flanks+measurement_build")->Unit(benchmark::kMillisecond);

void BM_EvaluateTrace(benchmark::State& state) {
  const auto& b = bench::default_scene();
  const auto m = workbench::gear_measurement(b.setup.geometry(), b.setup.ranges(), simulated_gear());
  for (auto _ : state)
    for (const auto& f : m.flanks) {
      benchmark::DoNotOptimize(evaluation::evaluate_trace(f.profile));
      benchmark::DoNotOptimize(evaluation::evaluate_trace(f.helix));
    }
  state.counters["points"] = benchmark::Counter(trace_points(m) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["traces"] = 2.0 * static_cast<double>(m.flanks.size());
}
BENCHMARK(BM_EvaluateTrace)->Name("EvaluateTrace/140traces")->Unit(benchmark::kMillisecond);

} // namespace
