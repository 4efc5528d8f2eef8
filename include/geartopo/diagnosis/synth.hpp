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

} // namespace geartopo::diagnosis
