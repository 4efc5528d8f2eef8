// Diagnosis speed: teeth 1 and 18 (7×9 grid, both flanks: 252 points) "measured" on the truth scene
// (scenes/truth-skmc1200w-mn14-z35.yaml, hidden thermal drift) with diagnosis::synthesize (0.5 µm noise, seed 1), then
// diagnosis::diagnose on the default scene with every library effect as a candidate, noise estimated from the
// residual (as `geartopo diagnose` without --noise-um). Counter `points`: measured points per second.
// Diagnose/scale/*: the same on dense grids of every tooth (35 teeth × both flanks × rows × cols: 10⁴, 10⁵, 10⁶ points),
// the scale of a scanned flank (issue 14: linear in the number of points). The measurement is synthesised once per
// size, outside the timing; CPU is the process' (all threads), wall the real time.
#include "bench_scene.hpp"

#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/synth.hpp"

#include <benchmark/benchmark.h>

#include <map>
#include <numeric>

using namespace geartopo;

namespace {

const std::vector<measurement::MeasuredPoint>& measured() {
  static const auto pts = [] {
    const auto& truth = bench::truth_scene();
    diagnosis::SynthOptions o; // teeth 1 and 18, 7×9, 0.5 µm, seed 1
    return measurement::measured_points(diagnosis::synthesize(truth.setup, truth.process(), o), truth.setup.geometry(),
                                        "synthetic");
  }();
  return pts;
}

void BM_Synthesize(benchmark::State& state) {
  const auto& truth = bench::truth_scene();
  size_t n = 0;
  for (auto _ : state) {
    const auto rows = diagnosis::synthesize(truth.setup, truth.process(), diagnosis::SynthOptions{});
    n = rows.size();
    benchmark::DoNotOptimize(rows.data());
  }
  state.counters["points"] = benchmark::Counter(static_cast<double>(n) * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Synthesize)->Name("Synthesize/teeth1+18/grid7x9")->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_Diagnose(benchmark::State& state) {
  const auto& model = bench::default_scene();
  const auto& pts = measured();
  std::string chosen;
  for (auto _ : state) {
    const auto d = diagnosis::diagnose(model.setup, model.process(), pts, model.effect_types(), diagnosis::DiagnoseOptions{});
    chosen = d.chosen ? d.chosen->name() : "none";
    benchmark::DoNotOptimize(d.ranked.data());
  }
  state.SetLabel("chosen: " + chosen);
  state.counters["points"] = benchmark::Counter(static_cast<double>(pts.size()) * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Diagnose)->Name("Diagnose/all_library_effects/teeth1+18")->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(2);

// Every tooth, rows × cols per flank (rows = cols = side), 0.5 µm noise, seed 1: 70·side² points.
const std::vector<measurement::MeasuredPoint>& dense_measurement(int side) {
  static std::map<int, std::vector<measurement::MeasuredPoint>> cache;
  auto it = cache.find(side);
  if (it == cache.end()) {
    const auto& truth = bench::truth_scene();
    diagnosis::SynthOptions o;
    o.teeth.resize(static_cast<size_t>(truth.setup.geometry().teeth()));
    std::iota(o.teeth.begin(), o.teeth.end(), 1);
    o.rows = o.cols = side;
    it = cache.emplace(side, measurement::measured_points(diagnosis::synthesize(truth.setup, truth.process(), o),
                                                          truth.setup.geometry(), "synthetic")).first;
  }
  return it->second;
}

void BM_DiagnoseScale(benchmark::State& state) {
  const auto& model = bench::default_scene();
  const auto& pts = dense_measurement(static_cast<int>(state.range(0)));
  std::string chosen;
  for (auto _ : state) {
    const auto d = diagnosis::diagnose(model.setup, model.process(), pts, model.effect_types(), diagnosis::DiagnoseOptions{});
    chosen = d.chosen ? d.chosen->name() : "none";
    benchmark::DoNotOptimize(d.ranked.data());
  }
  state.SetLabel(std::to_string(pts.size()) + " points, chosen: " + chosen);
  state.counters["points"] = benchmark::Counter(static_cast<double>(pts.size()) * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
// side 12: 10 080 points; 38: 101 080; 120: 1 008 000.
BENCHMARK(BM_DiagnoseScale)->Name("Diagnose/scale/all_teeth")->Arg(12)->Arg(38)->Arg(120)->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kSecond)->Iterations(1);

} // namespace

namespace {

// Beyond the library (docs/diagnosis.md): the default scene measured with the A axis' zero position drifting by
// 40 µrad/min — no library effect explains it, so every candidate is fitted and then the 43 components under their
// laws and both wheel flanks. 252 points (teeth 1 and 18) and every tooth on 38 × 38 per flank (101 080 points).
const workbench::Workbench& drifting_a_axis() {
  static const workbench::Workbench b = [] {
    scene::Scene s = scene::load_scene(bench::kDefaultScene);
    machine::ComponentChange c;
    c.component = machine::ComponentId::E_AOA;
    c.law = machine::ChangeLaw::LinearInTime;
    c.size = 40e-6 / 60.0; // rad/s
    s.machine_changes.push_back(c);
    return workbench::Workbench(std::move(s));
  }();
  return b;
}

void BM_DiagnoseBeyondLibrary(benchmark::State& state) {
  const auto& model = bench::default_scene();
  const auto& truth = drifting_a_axis();
  diagnosis::SynthOptions o;
  if (state.range(0) > 0) {
    o.teeth.resize(static_cast<size_t>(truth.setup.geometry().teeth()));
    std::iota(o.teeth.begin(), o.teeth.end(), 1);
    o.rows = o.cols = static_cast<int>(state.range(0));
  }
  const auto pts = measurement::measured_points(diagnosis::synthesize(truth.setup, truth.process(), o),
                                                truth.setup.geometry(), "synthetic");
  std::string chosen;
  for (auto _ : state) {
    const auto d = diagnosis::diagnose(model.setup, model.process(), pts, model.effect_types(), diagnosis::DiagnoseOptions{});
    chosen = d.chosen ? d.chosen->name() : "none";
    benchmark::DoNotOptimize(d.hypotheses.data());
  }
  state.SetLabel(std::to_string(pts.size()) + " points, chosen: " + chosen);
  state.counters["points"] = benchmark::Counter(static_cast<double>(pts.size()) * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
// 0: teeth 1 and 18 on the 7 × 9 grid (252 points); 38: every tooth, 38 × 38 per flank (101 080 points).
BENCHMARK(BM_DiagnoseBeyondLibrary)->Name("Diagnose/beyond_library/A_axis_drift")->Arg(0)->Arg(38)->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(1);

} // namespace
