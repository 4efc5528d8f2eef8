// Shared set-up for the grinding tests: the seed paper's gear on a 350 mm wheel, built once per test binary.
#pragma once

#include "../gears/gear_fixtures.hpp"
#include "grinding/grinding_setup.hpp"
#include "grinding/machine_process.hpp"
#include "grinding/topology.hpp"
#include "machine/error_source.hpp"

#include <gtest/gtest.h>

#include <memory>

namespace geartopo::test {

inline const grinding::GrindingSetup& paper_setup() {
  static const grinding::GrindingSetup setup(paper_gear(), {350.0, 0.0}, {});
  return setup;
}

/// Machine Z of the datum face used by the tests: inside the default Z stroke [0, 800] for the whole path.
inline constexpr double kDatumZ = 300.0;

/// A machine with the given error sources and the paper's strokes.
inline machine::MachineModel machine_with(std::vector<machine::ErrorSource> sources) {
  return machine::MachineModel(machine::Strokes::skmc_1200w(), std::move(sources));
}

inline std::vector<grinding::FlankTopology> simulate(const grinding::GrindingProcess& p, grinding::Method m,
                                                     std::vector<int> teeth = {1, 18}) {
  grinding::SimulationOptions o;
  o.method = m;
  o.teeth = std::move(teeth);
  o.profile_points = 20;
  o.helix_points = 20;
  return grinding::simulate_topology(paper_setup(), p, o);
}

} // namespace geartopo::test
