// The grinding process per path point on a chain described as data (issue 42) against the compiled-in CFXZAY: the
// wheel pose (exact) and the first-order error twist at the default scene's path points (sampled every 2 mm),
// through MachineProcess (the CFXZAY's own evaluator, the fast path the workbench keeps for it), through ChainProcess
// on the CFXZAY described as data (the same machine: the cost of the general chain), and through ChainProcess on the
// shipped CAFXZY scene. Counter `points`: path points evaluated per second (one thread).
#include "bench_scene.hpp"

#include "geartopo/grinding/chain_process.hpp"
#include "geartopo/machine/kinematic_chain.hpp"

#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

using namespace geartopo;

namespace {

const workbench::Workbench& cafxzy_scene() {
  static const workbench::Workbench b(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/cafxzy-mn14-z35.yaml");
  return b;
}

// a: evaluator (0 MachineProcess on the default scene, 1 ChainProcess of the CFXZAY on the default scene,
// 2 ChainProcess of the shipped CAFXZY scene), quantity (0 the exact pose, 1 the first-order twist).
void BM_ChainPoint(benchmark::State& state, std::vector<int64_t> a) {
  const auto& wb = a[0] == 2 ? cafxzy_scene() : bench::default_scene();
  std::unique_ptr<grinding::ChainProcess> as_data;
  if (a[0] == 1)
    as_data = std::make_unique<grinding::ChainProcess>(machine::cfxzay(), wb.machine, wb.scene.machine.datum_face_z_mm);
  const grinding::GrindingProcess& p = as_data ? *as_data : wb.machine_process;
  const std::vector<grinding::PathPoint> points = wb.setup.path().sample(2.0);
  for (auto _ : state)
    for (const auto& pp : points) {
      if (a[1] == 0) benchmark::DoNotOptimize(p.actual_wMg(pp));
      else benchmark::DoNotOptimize(p.error_twist_w(pp));
    }
  state.counters["points"] =
      benchmark::Counter(static_cast<double>(points.size() * state.iterations()), benchmark::Counter::kIsRate);
}

} // namespace

BENCHMARK_CAPTURE(BM_ChainPoint, MachineProcess_pose, std::vector<int64_t>{0, 0})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ChainPoint, ChainProcessCfxzay_pose, std::vector<int64_t>{1, 0})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ChainPoint, ChainProcessCafxzy_pose, std::vector<int64_t>{2, 0})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ChainPoint, MachineProcess_twist, std::vector<int64_t>{0, 1})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ChainPoint, ChainProcessCfxzay_twist, std::vector<int64_t>{1, 1})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ChainPoint, ChainProcessCafxzy_twist, std::vector<int64_t>{2, 1})->Unit(benchmark::kMicrosecond);
