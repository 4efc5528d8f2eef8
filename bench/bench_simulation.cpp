// Simulation speed on the default scene (scenes/skmc1200w-mn14-z35.yaml: 35 teeth, both flanks = 70 flanks).
//
// simulate_topology always computes the grid and both traces (SimulationOptions has no "no traces"; the minimum is
// 2 points per trace), so the `Simulate/*` cases are labelled with what they include: grid + 2-point traces is
// 63 + 4 points per flank. The `GridOnly/*` cases run exactly the grid loop of simulate_topology (same
// FlankDeviation::at calls, same parallel_for over flanks) through the public FlankDeviation API, without traces.
// Counter `points`: deviations computed per second (wall clock: the simulation is multi-threaded).
// `PoseEvaluationsPerPoint/*` counts the wheel poses (exact) or error twists (linear) asked for per point.
#include "bench_scene.hpp"

#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/core/parallel.hpp"
#include "geartopo/grinding/topology.hpp"

#include <benchmark/benchmark.h>

#include <atomic>
#include <vector>

using namespace geartopo;
using grinding::Method;

namespace {

Method method_of(int64_t m) { return m == 0 ? Method::Exact : Method::Linear; }

// The grid loop of simulate_topology (src/grinding/topology.cpp) without traces: every tooth, both flanks.
double grid_only(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& process, Method m, int rows,
                 int cols, int threads) {
  const auto& g = setup.geometry();
  const auto xis = grinding::grid_roll_lengths(setup.ranges(), rows);
  const auto zs = grinding::grid_axial_positions(setup.ranges(), cols);
  const grinding::FlankDeviation dev(setup.flanks(), setup.wheel(), setup.path(), process);
  const int flanks = 2 * g.teeth();
  std::vector<double> out(static_cast<size_t>(flanks) * xis.size() * zs.size());
  geartopo::parallel_for(flanks, threads, [&](int i) {
    const int tooth = i / 2 + 1;
    const auto flank = i % 2 == 0 ? geartopo::Flank::Left : geartopo::Flank::Right;
    size_t k = static_cast<size_t>(i) * xis.size() * zs.size();
    for (double xi : xis)
      for (double z : zs) out[k++] = 1e3 * dev.at(tooth, flank, xi, z, m).deviation_mm;
  });
  double sum = 0.0;
  for (double v : out) sum += v;
  return sum;
}

void set_points(benchmark::State& state, double points_per_run) {
  state.counters["points"] = benchmark::Counter(points_per_run * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
  state.counters["points_per_run"] = points_per_run;
}

// a: method (0 exact, 1 linear), rows, cols, threads (0: all hardware threads).
void BM_GridOnly(benchmark::State& state, std::vector<int64_t> a) {
  const auto& b = bench::default_scene();
  const Method m = method_of(a[0]);
  const int rows = static_cast<int>(a[1]), cols = static_cast<int>(a[2]);
  const int threads = static_cast<int>(a[3]);
  for (auto _ : state) benchmark::DoNotOptimize(grid_only(b.setup, b.process(), m, rows, cols, threads));
  set_points(state, 2.0 * b.setup.geometry().teeth() * rows * cols);
}

// a: method, rows, cols, profile_points, helix_points, dense_rows, dense_cols, threads.
void BM_Simulate(benchmark::State& state, std::vector<int64_t> a) {
  const auto& b = bench::default_scene();
  grinding::SimulationOptions o;
  o.method = method_of(a[0]);
  o.rows = static_cast<int>(a[1]);
  o.cols = static_cast<int>(a[2]);
  o.profile_points = static_cast<int>(a[3]);
  o.helix_points = static_cast<int>(a[4]);
  o.dense_rows = static_cast<int>(a[5]);
  o.dense_cols = static_cast<int>(a[6]);
  o.threads = static_cast<int>(a[7]);
  size_t points = 0;
  for (auto _ : state) {
    const auto topo = grinding::simulate_topology(b.setup, b.process(), o);
    points = 0;
    for (const auto& ft : topo) points += ft.grid.size() + ft.profile.size() + ft.helix.size() + ft.dense.size();
    benchmark::DoNotOptimize(topo.data());
  }
  set_points(state, static_cast<double>(points));
}

// How many wheel poses the exact search evaluates per point: the simulator behind a counting GrindingProcess.
class CountingProcess final : public grinding::GrindingProcess {
public:
  explicit CountingProcess(const grinding::GrindingProcess& inner) : inner_(inner) {}
  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override {
    poses.fetch_add(1, std::memory_order_relaxed);
    return inner_.actual_wMg(pp);
  }
  machine::Vector6d error_twist_w(const grinding::PathPoint& pp) const override {
    twists.fetch_add(1, std::memory_order_relaxed);
    return inner_.error_twist_w(pp);
  }
  double wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const override {
    return inner_.wheel_radius_error_mm(v, pp);
  }
  mutable std::atomic<long> poses{0}, twists{0};

private:
  const grinding::GrindingProcess& inner_;
};

void BM_PoseEvaluationsPerPoint(benchmark::State& state) {
  const auto& b = bench::default_scene();
  const CountingProcess counting(b.process());
  const Method m = method_of(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(grid_only(b.setup, counting, m, 7, 9, 1));
  const double points = 2.0 * b.setup.geometry().teeth() * 63 * static_cast<double>(state.iterations());
  state.counters["poses_per_point"] = static_cast<double>(counting.poses.load()) / points;
  state.counters["twists_per_point"] = static_cast<double>(counting.twists.load()) / points;
}
BENCHMARK(BM_PoseEvaluationsPerPoint)
    ->Name("PoseEvaluationsPerPoint/exact/7x9")->Arg(0)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PoseEvaluationsPerPoint)
    ->Name("PoseEvaluationsPerPoint/linear/7x9")->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);

struct SimCase {
  const char* name;
  std::vector<int64_t> args; // see BM_Simulate
};

// Registered by name (wall clock, ms). threads 0 = all hardware threads (2 here); threads 1 shows the scaling.
const bool registered = [] {
  const SimCase simulate[] = {
      {"Simulate/exact/grid7x9+traces2/threads:all", {0, 7, 9, 2, 2, 0, 0, 0}},
      {"Simulate/exact/grid7x9+traces2/threads:1", {0, 7, 9, 2, 2, 0, 0, 1}},
      {"Simulate/linear/grid7x9+traces2/threads:all", {1, 7, 9, 2, 2, 0, 0, 0}},
      {"Simulate/exact/grid7x9+traces100x150/threads:all", {0, 7, 9, 100, 150, 0, 0, 0}},
      {"Simulate/linear/grid7x9+traces100x150/threads:all", {1, 7, 9, 100, 150, 0, 0, 0}},
      {"Simulate/exact/dense50x100+grid7x9+traces2/threads:all", {0, 7, 9, 2, 2, 50, 100, 0}},
      {"Simulate/linear/dense50x100+grid7x9+traces2/threads:all", {1, 7, 9, 2, 2, 50, 100, 0}},
  };
  for (const auto& c : simulate) {
    auto* bm = benchmark::RegisterBenchmark(c.name, BM_Simulate, c.args)->UseRealTime()->Unit(benchmark::kMillisecond);
    if (c.args[5] > 0 && c.args[0] == 0) bm->Iterations(3); // dense exact: seconds per run
  }
  // The call geartopo.simulate(scene, teeth="all", threads=1) makes from Python (the scene's grid and traces), with
  // the process's CPU time beside the wall: bench/python_simulate.py measures the Python call the same way, and CPU
  // time on one thread is the figure a loaded machine leaves comparable (docs/performance.md, "Python").
  const SimCase as_python[] = {
      {"Simulate/exact/grid7x9+traces100x150/threads:1", {0, 7, 9, 100, 150, 0, 0, 1}},
      {"Simulate/linear/grid7x9+traces100x150/threads:1", {1, 7, 9, 100, 150, 0, 0, 1}},
  };
  for (const auto& c : as_python)
    benchmark::RegisterBenchmark(c.name, BM_Simulate, c.args)->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond);
  const SimCase grid[] = {
      {"GridOnly/exact/7x9/threads:all", {0, 7, 9, 0}},
      {"GridOnly/exact/7x9/threads:1", {0, 7, 9, 1}},
      {"GridOnly/linear/7x9/threads:all", {1, 7, 9, 0}},
      {"GridOnly/linear/7x9/threads:1", {1, 7, 9, 1}},
      {"GridOnly/exact/50x100/threads:all", {0, 50, 100, 0}},
      {"GridOnly/linear/50x100/threads:all", {1, 50, 100, 0}},
  };
  for (const auto& c : grid) {
    auto* bm = benchmark::RegisterBenchmark(c.name, BM_GridOnly, c.args)->UseRealTime()->Unit(benchmark::kMillisecond);
    if (c.args[1] * c.args[2] > 1000 && c.args[0] == 0) bm->Iterations(3);
  }
  return true;
}();

} // namespace
