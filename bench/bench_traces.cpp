// Measured traces at full scale (issue 28): an export of every tooth of the default gear, both flanks, three profile
// and three helix traces of 500 points (35 × 2 × 6 × 500 = 210 000 points), written from the documented structure
// (tests/trace_export_fixture.hpp) with the truth scene's deviations (hidden thermal drift) plus 0.3 µm noise
// once, outside the timing. Timed as a user waits for `geartopo compare` / `diagnose`: reading the export, then
// diagnosis::compare (noise estimated from the lines), or diagnosis::diagnose with every library effect. Target:
// compare and diagnose together < 5 s. Both report the CPU time of all threads beside the wall time (process_time).
#include "bench_scene.hpp"

#include "../tests/trace_export_fixture.hpp"

#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/effect_contribution.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/measurement/any_measurement.hpp"

#include <benchmark/benchmark.h>

#include <random>

using namespace geartopo;

namespace {

const trace_fixture::TempFile& full_export() {
  static const trace_fixture::TempFile file = [] {
    const auto& model = bench::default_scene();
    const auto& truth = bench::truth_scene();
    const auto& g = model.setup.geometry();
    trace_fixture::Layout l;
    l.teeth.clear();
    for (int t = 1; t <= g.teeth(); ++t) l.teeth.push_back(t);
    l.profile_z_mm = {20.0, 75.0, 130.0};
    const double xa = g.roll_length_at(g.root_form_diameter_mm()), xe = g.roll_length_at(g.tip_diameter_mm());
    for (const double f : {0.3, 0.5, 0.7}) l.helix_d_mm.push_back(g.diameter_at_roll_length(xa + f * (xe - xa)));
    l.profile_points = l.helix_points = 500;
    const trace_fixture::TempFile zeros("zeros.mka", trace_fixture::write_export(g, l, [](Flank, int, double, double) { return 0.0; }).text);
    const auto at = measurement::read_any_measurement(zeros.path.string(), model.setup);
    const auto values = diagnosis::predict(truth.setup, truth.process(), at, grinding::Method::Exact);
    std::mt19937_64 gen(1);
    std::normal_distribution<double> noise(0.0, 0.3);
    std::size_t next = 0;
    return trace_fixture::TempFile(
        "full.mka", trace_fixture::write_export(g, l, [&](Flank, int, double, double) { return values[next++] + noise(gen); }).text);
  }();
  return file;
}

void BM_CompareTraces(benchmark::State& state) {
  const auto& model = bench::default_scene();
  const auto& file = full_export();
  std::size_t n = 0;
  for (auto _ : state) {
    const auto pts = measurement::read_any_measurement(file.path.string(), model.setup);
    const auto c = diagnosis::compare(model.setup, model.process(), pts, 0.0);
    n = pts.size();
    benchmark::DoNotOptimize(c.residual_um.data());
  }
  state.counters["points"] = benchmark::Counter(static_cast<double>(n) * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CompareTraces)->Name("Compare/traces/35teeth_6x500")->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_DiagnoseTraces(benchmark::State& state) {
  const auto& model = bench::default_scene();
  const auto& file = full_export();
  std::string chosen;
  std::size_t n = 0;
  for (auto _ : state) {
    const auto pts = measurement::read_any_measurement(file.path.string(), model.setup);
    const auto d = diagnosis::diagnose(model.setup, model.process(), pts, model.effect_types(), diagnosis::DiagnoseOptions{});
    chosen = d.chosen ? d.chosen->name() : "none";
    n = pts.size();
    benchmark::DoNotOptimize(d.ranked.data());
  }
  state.SetLabel("chosen: " + chosen);
  state.counters["points"] = benchmark::Counter(static_cast<double>(n) * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DiagnoseTraces)->Name("Diagnose/traces/35teeth_6x500")->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(1);

// One evaluation of an effect's first-order deviation at all 210 000 points of the export (what a fit repeats for every
// trial value of a nonlinear parameter), on one thread: its CPU time per pass. Arg: 0 thermal_drift, 1 eccentricity.
void BM_DeviationPass(benchmark::State& state) {
  const auto& model = bench::default_scene();
  static const auto pts = measurement::read_any_measurement(full_export().path.string(), model.setup);
  static const diagnosis::EffectContribution at(model.setup, pts, 0);
  auto e = effects::make_effect(state.range(0) == 0 ? "thermal_drift" : "eccentricity");
  e->bind(model.setup);
  auto v = e->values();
  v[0] = 5.0, v[1] = 3.0;
  e->set_values(v);
  const effects::Effect* list[] = {e.get()};
  for (auto _ : state) benchmark::DoNotOptimize(at.deviation_um(list, 1).data());
  state.SetLabel(std::string(e->type()));
  state.counters["points"] = benchmark::Counter(static_cast<double>(pts.size()) * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DeviationPass)->Name("DeviationPass/traces/35teeth_6x500/threads:1")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

} // namespace
