// Compensation speed on the default scene: compensation::compute_corrections with the flank method and the default
// options (2 mm path step, 15 contact points per flank, up to 12 Newton iterations per pose), for every space.
// Counter `rows`: correction-table rows (path samples) per second. Wall clock (compute_corrections may use threads).
#include "bench_scene.hpp"

#include "geartopo/compensation/compensator.hpp"

#include <benchmark/benchmark.h>

using namespace geartopo;

namespace {

void BM_Compensation(benchmark::State& state) {
  const auto& b = bench::default_scene();
  compensation::CompensationOptions o;
  o.method = state.range(0) == 0 ? compensation::Method::Flank : compensation::Method::Paper;
  const compensation::StrokeCheck strokes{b.machine, b.scene.machine.datum_face_z_mm};
  size_t rows = 0;
  for (auto _ : state) {
    const auto table = compensation::compute_corrections(b.setup, b.process(), strokes, o);
    rows = table.rows().size();
    benchmark::DoNotOptimize(table.rows().data());
  }
  state.counters["rows"] = benchmark::Counter(static_cast<double>(rows) * static_cast<double>(state.iterations()),
                                              benchmark::Counter::kIsRate);
  state.counters["rows_per_run"] = static_cast<double>(rows);
}
BENCHMARK(BM_Compensation)->Name("Compensation/flank/step2mm")->Arg(0)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Compensation)->Name("Compensation/paper/step2mm")->Arg(1)->UseRealTime()->Unit(benchmark::kMillisecond);

} // namespace
