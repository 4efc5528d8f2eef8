// ISO 1328-1 evaluation speed on a simulated gear: the default scene simulated once (exact, all 35 teeth, the scene's
// 100-point profile and 150-point helix traces), then
//   EvaluateGear  — evaluation::evaluate_gear on all 70 flanks with pitch and runout, the measurement built from the
//                   topology exactly as src/app/iso_report.cpp does (gear_measurement is app-internal: copied here);
//   EvaluateTrace — evaluation::evaluate_trace on the 140 traces (70 profile + 70 helix).
// Counter `points`: trace points evaluated per second.
#include "bench_scene.hpp"

#include "evaluation/gear_evaluation.hpp"
#include "evaluation/trace.hpp"
#include "grinding/topology.hpp"

#include <benchmark/benchmark.h>

#include <numbers>

using namespace geartopo;

namespace {

evaluation::Side side_of(gears::Flank f) { return f == gears::Flank::Right ? evaluation::Side::Right : evaluation::Side::Left; }

// Copy of the file-local helper of src/app/iso_report.cpp.
double at_z(const std::vector<grinding::TracePoint>& helix, double z) {
  for (size_t i = 1; i < helix.size(); ++i)
    if (helix[i].z_mm >= z) {
      const auto &a = helix[i - 1], &b = helix[i];
      const double t = (z - a.z_mm) / (b.z_mm - a.z_mm);
      return a.deviation_um + t * (b.deviation_um - a.deviation_um);
    }
  return helix.back().deviation_um;
}

// Copy of app::gear_measurement (src/app/iso_report.cpp), which the app does not export.
evaluation::GearMeasurement gear_measurement(const gears::GearGeometry& g, const gears::EvaluationRanges& r,
                                             const std::vector<grinding::FlankTopology>& topo) {
  evaluation::GearMeasurement m;
  double d_m = 0.0;
  for (const auto& ft : topo) {
    evaluation::FlankMeasurement fm;
    fm.tooth = ft.tooth;
    fm.side = side_of(ft.flank);
    for (const auto& p : ft.profile) fm.profile.position_mm.push_back(p.roll_length_mm), fm.profile.deviation_um.push_back(p.deviation_um);
    fm.profile.range_start_mm = r.xi_eval_start;
    fm.profile.range_end_mm = r.xi_eval_end;
    for (const auto& p : ft.helix) fm.helix.position_mm.push_back(p.z_mm), fm.helix.deviation_um.push_back(p.deviation_um);
    fm.helix.range_start_mm = r.z_eval_start;
    fm.helix.range_end_mm = r.z_eval_end;
    m.flanks.push_back(std::move(fm));
    if (!ft.helix.empty()) {
      m.pitch_points.push_back({ft.tooth, side_of(ft.flank), at_z(ft.helix, 0.5 * g.spec().face_width_mm)});
      d_m = ft.helix.front().diameter_mm;
    }
  }
  if (d_m > 0.0) {
    evaluation::PitchGeometry pg;
    pg.base_helix_angle_rad = g.base_helix_angle();
    pg.transverse_pressure_angle_rad = g.transverse_pressure_angle_at(d_m);
    pg.space_half_angle_rad = std::numbers::pi / g.teeth() - g.transverse_tooth_thickness_at(d_m) / d_m;
    m.pitch_geometry = pg;
  }
  return m;
}

const std::vector<grinding::FlankTopology>& simulated_gear() {
  static const auto topo = [] {
    const auto& b = bench::default_scene();
    grinding::SimulationOptions o;
    o.profile_points = b.sc.grid.profile_points;
    o.helix_points = b.sc.grid.helix_points;
    return grinding::simulate_topology(b.setup, b.actual(), o);
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
  const auto m = gear_measurement(g, b.setup.ranges(), simulated_gear());
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
  for (auto _ : state) benchmark::DoNotOptimize(evaluation::evaluate_gear(gear_measurement(g, b.setup.ranges(), topo), p));
  state.counters["points"] = benchmark::Counter(trace_points(gear_measurement(g, b.setup.ranges(), topo)) *
                                                    static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
BENCHMARK(BM_EvaluateIso)->Name("EvaluateGear/70flanks+measurement_build")->Unit(benchmark::kMillisecond);

void BM_EvaluateTrace(benchmark::State& state) {
  const auto& b = bench::default_scene();
  const auto m = gear_measurement(b.setup.geometry(), b.setup.ranges(), simulated_gear());
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
