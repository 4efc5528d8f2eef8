// Monte Carlo prediction speed on the default scene (docs/monte-carlo.md): pipeline::run_monte_carlo with the flank
// corrections of the scene, the scene's grid (7×9, 100/150-point traces, all 35 teeth, exact method), two gears per
// sample. Arg: the number of samples (20: a quick figure; 1000: the target, 60 s on the 2 cores).
// Counter `samples`: samples per second (wall clock; samples run in parallel on all cores). CPU is the process' CPU
// time (all threads): CPU / samples is the cost of one sample whatever the load of a shared machine.
#include "bench_scene.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"

#include <benchmark/benchmark.h>

using namespace geartopo;

namespace {

void BM_MonteCarlo(benchmark::State& state) {
  const auto& b = bench::default_scene();
  const compensation::CompensationOptions co;
  static const auto table =
      compensation::compute_corrections(b.setup, b.process(), {b.machine, b.scene.machine.datum_face_z_mm}, co);
  pipeline::MonteCarloOptions o;
  o.samples = state.range(0);
  for (auto _ : state) {
    const auto run = pipeline::run_monte_carlo(b, table, o);
    benchmark::DoNotOptimize(run.samples.data());
  }
  state.counters["samples"] = benchmark::Counter(static_cast<double>(o.samples) * static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
}
BENCHMARK(BM_MonteCarlo)->Name("MonteCarlo/default/grid7x9")->Arg(20)->Arg(1000)->Iterations(1)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kSecond);

} // namespace
