#include "geartopo/diagnosis/synth.hpp"

#include "geartopo/core/limits.hpp"
#include "geartopo/core/random.hpp"

namespace geartopo::diagnosis {

std::vector<grinding::TopologyRow> synthesize(const grinding::GrindingSetup& truth, const grinding::GrindingProcess& process,
                                              const SynthOptions& o) {
  limits::require(limits::synthetic_noise_um_refusal(o.noise_um), "synthesize: noise_um");
  grinding::SimulationOptions so;
  so.teeth = o.teeth;
  so.rows = o.rows;
  so.cols = o.cols;
  so.profile_points = so.helix_points = 2; // traces are not measured here
  so.keep_going = o.keep_going;
  auto rows = grinding::topology_rows(grinding::simulate_topology(truth, process, so));
  // One engine drawn in file order: the same seed gives the same file whatever the thread count.
  random::SplitMix64 rng(o.seed); // core/random.hpp: the same file with every standard library
  for (auto& r : rows) r.deviation_um += o.noise_um * rng.normal();
  return rows;
}

std::vector<grinding::FlankTopology> synthesize_traces(const grinding::GrindingSetup& truth,
                                                       const grinding::GrindingProcess& process, const SynthOptions& o,
                                                       int profile_points, int helix_points) {
  limits::require(limits::synthetic_noise_um_refusal(o.noise_um), "synthesize_traces: noise_um");
  grinding::SimulationOptions so;
  so.teeth = o.teeth;
  so.rows = so.cols = 2; // the grid is not measured here
  so.profile_points = profile_points;
  so.helix_points = helix_points;
  so.keep_going = o.keep_going;
  auto topo = grinding::simulate_topology(truth, process, so);
  random::SplitMix64 rng(o.seed);
  for (auto& ft : topo) ft.grid.clear();
  add_probe_noise(topo, o.noise_um, [&] { return rng.normal(); });
  return topo;
}

void add_probe_noise(std::vector<grinding::FlankTopology>& topo, double noise_um, const std::function<double()>& standard_normal) {
  limits::require(limits::synthetic_noise_um_refusal(noise_um), "add_probe_noise: noise_um");
  for (auto& ft : topo) {
    for (auto* trace : {&ft.profile, &ft.helix})
      for (auto& p : *trace) p.deviation_um += noise_um * standard_normal();
    for (auto& p : ft.grid) p.deviation_um += noise_um * standard_normal();
  }
}

} // namespace geartopo::diagnosis
