// Series speed (issue 41: 20 gears × 252 points in under 5 s on 2 cores): 20 gears of the default scene, each the
// simulator's profile and helix traces of teeth 1 and 18 (30 + 33 points per flank: 252 points) plus a slow drift and
// 0.3 µm noise, written once as traces CSV with their series file outside the timing; timed: reading the series, every
// gear compared with the model and evaluated to ISO 1328-1, every quantity's across-series fit, the prediction.
#include "bench_scene.hpp"

#include "geartopo/core/random.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/series/series_analysis.hpp"

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace geartopo;

namespace {

std::filesystem::path write_series(int gears) {
  const auto dir = std::filesystem::temp_directory_path() / "geartopo_bench_series";
  std::filesystem::create_directories(dir);
  grinding::SimulationOptions o;
  o.teeth = {1, 18};
  o.profile_points = 30;
  o.helix_points = 33;
  const auto& wb = bench::default_scene();
  const auto base = grinding::simulate_topology(wb.setup, wb.process(), o);
  random::SplitMix64 rng(5);
  std::string yaml = fmt::format("scene: {}\ngears:\n", bench::kDefaultScene);
  for (int k = 0; k < gears; ++k) {
    auto t = base;
    const double drift = 4.0 * (1.0 - std::exp(-k / 6.0));
    for (auto& ft : t)
      for (auto* trace : {&ft.profile, &ft.helix})
        for (auto& p : *trace) p.deviation_um += drift + 0.3 * rng.normal();
    const auto file = dir / fmt::format("gear{:02}.csv", k + 1);
    grinding::write_traces_csv(file, t);
    yaml += fmt::format("  - measurement: {}\n    start_s: {}\n", file.string(), 600 * k);
  }
  std::ofstream(dir / "series.yaml") << yaml;
  return dir / "series.yaml";
}

void BM_Series20Gears(benchmark::State& state) {
  const auto file = write_series(20);
  const auto& wb = bench::default_scene();
  for (auto _ : state) {
    const auto spec = series::load_series(file, series::strokes_per_gear(wb));
    const auto r = series::analyse_series(spec, wb);
    benchmark::DoNotOptimize(r.quantities.data());
  }
  std::filesystem::remove_all(file.parent_path());
}
BENCHMARK(BM_Series20Gears)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

} // namespace
