// geartopo — synthetic CMM measurements: the topology a truth scene's machine would leave, on the scene's grid, for
// chosen teeth, plus Gaussian probe noise. Deterministic for a given seed. Units: µm.
#pragma once

#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/topology_csv.hpp"

#include <cstdint>
#include <vector>

namespace geartopo::diagnosis {

struct SynthOptions {
  std::vector<int> teeth{1, 18};
  int rows = 7, cols = 9;
  double noise_um = 0.5;
  std::uint64_t seed = 1;
};

std::vector<grinding::TopologyRow> synthesize(const grinding::GrindingSetup& truth, const grinding::GrindingProcess& process,
                                              const SynthOptions& options);

/// The same gear as a gear measuring machine measures it: per flank of the chosen teeth one profile trace (profile_points
/// along the evaluation range at mid face) and one helix trace (helix_points), as grinding::simulate_topology lays
/// them, each point plus Gaussian probe noise drawn in file order (flank by flank, profile then helix). For
/// `geartopo evaluate --traces`.
std::vector<grinding::FlankTopology> synthesize_traces(const grinding::GrindingSetup& truth,
                                                       const grinding::GrindingProcess& process, const SynthOptions& options,
                                                       int profile_points, int helix_points);

} // namespace geartopo::diagnosis
