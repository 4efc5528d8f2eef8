// The gear as drawn (docs/modifications.md): simulating the crowned default gear against the plain one (target: a
// modified gear costs ≤ 1.5× the unmodified one, 7×9 and dense), and solving its twist-free motions (target < 5 s).
// Compare `Simulate/exact/…/crowned` with the same case of bench_simulation.cpp (`Simulate/exact/…/threads:all`).
#include "bench_scene.hpp"

#include "geartopo/compensation/design_motion.hpp"
#include "geartopo/grinding/topology.hpp"

#include <benchmark/benchmark.h>

using namespace geartopo;

namespace {

void BM_SimulateCrowned(benchmark::State& state) {
  const auto& b = bench::crowned_scene();
  grinding::SimulationOptions o;
  o.rows = 7;
  o.cols = 9;
  o.profile_points = o.helix_points = 2;
  o.dense_rows = static_cast<int>(state.range(0));
  o.dense_cols = static_cast<int>(state.range(1));
  o.threads = static_cast<int>(state.range(2)); // 0: all hardware threads
  for (auto _ : state) benchmark::DoNotOptimize(grinding::simulate_topology(b.setup, b.process(), o).data());
}
// Args: dense rows, dense cols, threads (0: all). threads 1 compares with `…/threads:1` of bench_simulation.cpp
// where the machine is shared (CPU time of one thread is not inflated by other users' load).
BENCHMARK(BM_SimulateCrowned)
    ->Name("Simulate/exact/grid7x9+traces2/crowned")->Args({0, 0, 0})->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulateCrowned)
    ->Name("Simulate/exact/grid7x9+traces2/crowned/threads:1")->Args({0, 0, 1})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulateCrowned)
    ->Name("Simulate/exact/dense50x100+grid7x9+traces2/crowned")->Args({50, 100, 0})->Iterations(3)->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_TwistFreeMotions(benchmark::State& state) {
  const auto& b = bench::crowned_scene();
  for (auto _ : state)
    benchmark::DoNotOptimize(compensation::design_motions(b.setup, grinding::LeadCrowning::TwistFree,
                                                          {b.machine, b.scene.machine.datum_face_z_mm})
                                 .rows()
                                 .size());
}
BENCHMARK(BM_TwistFreeMotions)->Name("DesignMotions/twist_free/default")->UseRealTime()->Unit(benchmark::kMillisecond);

} // namespace
