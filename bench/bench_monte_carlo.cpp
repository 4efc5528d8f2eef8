// Monte Carlo prediction speed on the default scene (docs/monte-carlo.md): pipeline::run_monte_carlo with the flank
// corrections of the scene, the scene's grid (7×9, 100/150-point traces, all 35 teeth), two gears per sample.
// `MonteCarlo/default/grid7x9/N`: the default sampling (linear samples after the check of 4 exact ones, with the
// decomposition by source; issue 25's target: 1000 samples < 3 s on the 2 cores); `…/exact/N`: every sample simulated
// exactly (--exact-samples). Arg: the number of samples.
// Counter `samples`: samples per second (wall clock; samples run in parallel on all cores). CPU is the process' CPU
// time (all threads): CPU / samples is the cost of one sample whatever the load of a shared machine.
//
// `MonteCarloSample/dense50x100/all_teeth` (issue 15's second target, < 0.5 s per sample): what one sample does —
// the true machine drawn within the scene's uncertainties, gear 1 ground uncorrected and gear 2 with the rounded
// corrections, each stroke off by its repeatability draw — with the scene's grid and traces plus a dense 50×100 grid
// on every flank of all 35 teeth, exact method, and both gears evaluated per ISO 1328-1. run_monte_carlo has no dense
// grid, so the sample is put together here from the same public parts (the draws from a fixed-seed std::mt19937_64,
// not run_monte_carlo's SplitMix64 streams: the cost does not depend on the values drawn). The two gears run on all
// cores (parallel over the 70 flanks); wall time is per sample, CPU time the process' (all threads).
#include "bench_scene.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/grinding/machine_process.hpp"
#include "geartopo/grinding/topology_plan.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>
#include <set>

using namespace geartopo;

namespace {

const compensation::CorrectionTable& default_corrections() {
  const auto& b = bench::default_scene();
  static const auto table = compensation::compute_corrections(b.setup, b.process(), {b.machine, b.scene.machine.datum_face_z_mm},
                                                              compensation::CompensationOptions{});
  return table;
}

void run_samples(benchmark::State& state, pipeline::Sampling sampling) {
  const auto& b = bench::default_scene();
  const auto& table = default_corrections();
  pipeline::MonteCarloOptions o;
  o.samples = state.range(0);
  o.sampling = sampling;
  for (auto _ : state) {
    const auto run = pipeline::run_monte_carlo(b, table, o);
    benchmark::DoNotOptimize(run.samples.data());
  }
  state.counters["samples"] = benchmark::Counter(static_cast<double>(o.samples) * static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
}
void BM_MonteCarlo(benchmark::State& state) { run_samples(state, pipeline::Sampling::Checked); }
void BM_MonteCarloExact(benchmark::State& state) { run_samples(state, pipeline::Sampling::Exact); }
BENCHMARK(BM_MonteCarlo)->Name("MonteCarlo/default/grid7x9")->Arg(20)->Arg(1000)->Iterations(1)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_MonteCarloExact)->Name("MonteCarlo/default/grid7x9/exact")->Arg(20)->Arg(1000)->Iterations(1)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kSecond);

/// The dense sample's points: the scene's grid, traces and a dense 50×100 grid on all 70 flanks.
grinding::SimulationOptions dense_sample_options() {
  const auto& b = bench::default_scene();
  grinding::SimulationOptions so;
  so.rows = b.scene.grid.rows;
  so.cols = b.scene.grid.cols;
  so.profile_points = b.scene.grid.profile_points;
  so.helix_points = b.scene.grid.helix_points;
  so.dense_rows = 50;
  so.dense_cols = 100;
  so.threads = 0; // both gears on all cores, parallel over flanks
  return so;
}

/// A correction table whose every row is `base`'s plus its space's offset (X, Y, Z, A, C).
void BM_MonteCarloDenseSample(benchmark::State& state) {
  const auto& b = bench::default_scene();
  const auto& unc = b.scene.machine.uncertainty;
  const auto applied = pipeline::rounded_to_resolution(default_corrections(), unc.resolution);
  std::vector<compensation::CorrectionRow> zero_rows = applied.rows();
  for (auto& r : zero_rows) r.correction.setZero();
  const compensation::CorrectionTable uncorrected(std::move(zero_rows));
  std::set<int> spaces;
  for (const auto& r : applied.rows()) spaces.insert(r.space);

  const grinding::SimulationOptions so = dense_sample_options();
  const grinding::TopologyPlan plan(b.setup, so);
  const auto& g = b.setup.geometry();

  std::mt19937_64 rng(15);
  std::normal_distribution<double> normal;
  for (auto _ : state) {
    // The true machine: every component of the scene's map plus a calibration offset drawn from N(0, u²).
    std::vector<machine::ErrorSource> truth;
    for (int k = 0; k < machine::kComponentCount; ++k)
      truth.push_back(b.machine.source(machine::component_at(k)).shifted(unc.component_u[static_cast<size_t>(k)] * normal(rng)));
    // Repeatability draws, one per stroke and axis (the Monte Carlo's own draw and offsetting, pipeline/monte_carlo.hpp).
    const auto draw = [&] { return normal(rng); };
    const auto off_before = pipeline::draw_stroke_offsets(spaces, unc.repeatability, draw);
    const auto off_after = pipeline::draw_stroke_offsets(spaces, unc.repeatability, draw);
    const machine::MachineModel model(b.machine.strokes(), std::move(truth));
    const grinding::MachineProcess machine_process(model, b.scene.machine.datum_face_z_mm);
    std::unique_ptr<effects::EffectsProcess> with_effects;
    if (!b.effects.empty()) with_effects = std::make_unique<effects::EffectsProcess>(machine_process, b.effects);
    const grinding::GrindingProcess& true_machine =
        with_effects ? static_cast<const grinding::GrindingProcess&>(*with_effects) : machine_process;
    const auto table_before = pipeline::with_stroke_offsets(uncorrected, off_before);
    const auto table_after = pipeline::with_stroke_offsets(applied, off_after);
    const compensation::CompensatedProcess gear1(true_machine, table_before), gear2(true_machine, table_after);
    for (const auto* gear : {&gear1, &gear2}) {
      const auto topo = plan.simulate(*gear, so.threads);
      const auto q = pipeline::gear_quantities(workbench::evaluate_iso(g, b.setup.ranges(), topo, {}), topo);
      benchmark::DoNotOptimize(q.values.data());
    }
  }
  state.counters["points_per_gear"] = static_cast<double>(plan.points());
}
BENCHMARK(BM_MonteCarloDenseSample)
    ->Name("MonteCarloSample/dense50x100/all_teeth")
    ->Iterations(3)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kSecond);

/// Building the dense sample's plan (once per run: the points' geometry and the ideal depth curvature that lets every
/// sample ask 3 wheel poses per point instead of 4), to weigh against one sample above.
void BM_DenseSamplePlan(benchmark::State& state) {
  const auto& b = bench::default_scene();
  const grinding::SimulationOptions so = dense_sample_options();
  for (auto _ : state) {
    const grinding::TopologyPlan plan(b.setup, so);
    benchmark::DoNotOptimize(plan.points());
  }
}
BENCHMARK(BM_DenseSamplePlan)
    ->Name("TopologyPlan/dense50x100/all_teeth")
    ->Iterations(3)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kSecond);

} // namespace
