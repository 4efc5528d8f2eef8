// geartopo — synthetic CMM measurements: the topology a truth scene's machine would leave, on the scene's grid, for
// chosen teeth, plus Gaussian probe noise. Deterministic for a given seed. Units: µm.
#pragma once

#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/topology_csv.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace geartopo::diagnosis {

struct SynthOptions {
  std::vector<int> teeth{1, 18};
  int rows = 7, cols = 9;
  double noise_um = 0.5;
  std::uint64_t seed = 1;
  /// grinding::SimulationOptions::keep_going of the simulation (a Ctrl-C check; may throw to stop).
  std::function<void()> keep_going;
};

std::vector<grinding::TopologyRow> synthesize(const grinding::GrindingSetup& truth, const grinding::GrindingProcess& process,
                                              const SynthOptions& options);

/// Gaussian probe noise on a measured gear: flank by flank, each point of the profile trace, then of the helix
/// trace, then of the grid plus noise_um times a draw of `standard_normal`, in that order. The noise of
/// synthesize_traces (no grid there) and of every Monte Carlo sample with MonteCarloOptions::probe_noise_um.
void add_probe_noise(std::vector<grinding::FlankTopology>& topo, double noise_um, const std::function<double()>& standard_normal);

/// The same gear as a gear measuring machine measures it: per flank of the chosen teeth one profile trace (profile_points
/// along the evaluation range at mid face) and one helix trace (helix_points), as grinding::simulate_topology lays
/// them, each point plus Gaussian probe noise drawn in file order (flank by flank, profile then helix). For
/// `geartopo evaluate --traces`.
std::vector<grinding::FlankTopology> synthesize_traces(const grinding::GrindingSetup& truth,
                                                       const grinding::GrindingProcess& process, const SynthOptions& options,
                                                       int profile_points, int helix_points);

} // namespace geartopo::diagnosis
