// A law declared in the scene (custom_effects: a muParser expression, effects/custom_effect.hpp) against the same law
// compiled as a C++ plug-in, per simulated point (issue 40: the declared one may cost at most 2×). Both go through the
// same contact map (ContactMap: which flank point the wheel touches at v), so the difference is the expression's
// evaluation alone: the thread's compiled copy found, the parameters and the 19 variables copied in, the bytecode run.
// Exact method on the default scene's grid (tooth 1 … 35, both flanks, 7 × 9), all hardware threads.
// Run: build/bin/geartopo_bench --benchmark_filter=CustomLaw
#include "bench_scene.hpp"

#include "geartopo/core/units.hpp"
#include "geartopo/effects/custom_effect.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/scene/scene.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace geartopo;

namespace {

const char* kLaw = "-shrink_um_per_mm * (x_mm*nx + y_mm*ny) * (1 - exp(-t_s / tau_s))";

/// The same law in C++, through the same contact map as the declared one.
class CompiledWarming final : public effects::Effect {
public:
  CompiledWarming() { init_defaults(); }
  std::string_view type() const override { return "compiled_warming"; }
  std::string_view explanation() const override { return kLaw; }
  const std::vector<effects::ParameterSpec>& parameters() const override {
    static const std::vector<effects::ParameterSpec> p{{"shrink_um_per_mm", "", 0.04, -0.1, 0.1, 0.01},
                                                       {"tau_s", "", 200.0, 30.0, 20000.0, 2000.0}};
    return p;
  }
  std::unique_ptr<effects::Effect> clone() const override { return std::make_unique<CompiledWarming>(*this); }
  void bind(const grinding::GrindingSetup& setup) override {
    Effect::bind(setup);
    map_ = std::make_shared<const effects::ContactMap>(setup);
  }
  double wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const override {
    const auto c = map_->at(v, pp, 0);
    const double e_um = -value(0) * (c.x_mm * c.nx + c.y_mm * c.ny) * (1.0 - std::exp(-c.t_s / value(1)));
    return -units::mm_from_um(e_um) / setup().wheel().normal_per_radial(v);
  }

private:
  std::shared_ptr<const effects::ContactMap> map_;
};

const workbench::Workbench& declared_scene() {
  static const workbench::Workbench b([] {
    std::ifstream in(bench::kDefaultScene);
    std::stringstream s;
    s << in.rdbuf();
    return scene::parse_scene(s.str() + "\ncustom_effects:\n  - name: bench_warming\n    parameters:\n"
                                        "      shrink_um_per_mm: {value: 0.04, min: -0.1, max: 0.1, unit: um_per_mm}\n"
                                        "      tau_s: {value: 200, min: 30, max: 20000, unit: s}\n"
                                        "    deviation_um: \"" + std::string(kLaw) + "\"\n",
                              bench::kDefaultScene);
  }());
  return b;
}

grinding::SimulationOptions grid_options() {
  grinding::SimulationOptions o;
  o.rows = 7, o.cols = 9, o.profile_points = 2, o.helix_points = 2;
  return o;
}

// 0: no effect (the machine alone), 1: the compiled plug-in, 2: the scene's declared law.
void BM_CustomLaw(benchmark::State& state) {
  const auto& plain = bench::default_scene();
  const auto& declared = declared_scene();
  CompiledWarming compiled;
  compiled.bind(plain.setup);
  const effects::EffectsProcess with_compiled(plain.process(), std::vector<const effects::Effect*>{&compiled});
  const grinding::GrindingProcess* process = &plain.process();
  if (state.range(0) == 1) process = &with_compiled;
  if (state.range(0) == 2) process = &declared.process();
  const auto o = grid_options();
  for (auto _ : state) benchmark::DoNotOptimize(grinding::simulate_topology(plain.setup, *process, o).data());
  const double points = 2.0 * plain.setup.geometry().teeth() * (o.rows * o.cols + 4);
  state.counters["points"] = benchmark::Counter(points * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(state.range(0) == 0 ? "no effect" : state.range(0) == 1 ? "compiled plug-in" : "declared in the scene");
}
BENCHMARK(BM_CustomLaw)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace
