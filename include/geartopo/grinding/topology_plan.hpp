// geartopo — the points of a topology simulation, computed once and simulated under many processes (Monte Carlo:
// two gears per sample, docs/monte-carlo.md). What a flank point needs that does not depend on the process — its
// nominal position and normal, the space that grinds it and its nominal stroke position Z₀ (FlankDeviation::Target)
// — is computed here once, with the depth's curvature along the stroke under the ideal process, so that the exact
// search asks 3 wheel poses per point instead of 4; simulate() then runs the exact (or linear) search of
// FlankDeviation on each point. simulate(process) gives what simulate_topology(setup, process, options) gives, to
// 1e-6 µm (tests/grinding/test_topology_plan.cpp; the two searches' vertices differ at the 1e-13 mm level).
// Units: mm in, µm deviations out (as simulate_topology).
#pragma once

#include "geartopo/grinding/topology.hpp"

#include <vector>

namespace geartopo::grinding {

class TopologyPlan {
public:
  /// The points simulate_topology(setup, ·, options) would compute. Throws std::invalid_argument as
  /// simulate_topology does. `setup` must outlive the plan.
  TopologyPlan(const GrindingSetup& setup, const SimulationOptions& options);

  /// The topology under `process` (options.threads threads, results independent of them). Throws std::runtime_error
  /// naming the first point the wheel never reaches (grinding::require_reached).
  std::vector<FlankTopology> simulate(const GrindingProcess& process, int threads) const;

  long long points() const;

  /// The first-order model's contact of every point (LinearContact, flank_deviation.hpp: generating pose, point, normal,
  /// wheel coordinate), flank by flank in simulate()'s order and within a flank grid, profile, helix, dense: where the
  /// Monte Carlo's first-order sensitivities of the topology are evaluated (pipeline/monte_carlo.hpp).
  std::vector<LinearContact> linear_contacts() const;

private:
  struct FlankPlan {
    int tooth;
    geartopo::Flank flank;
    std::vector<FlankDeviation::Target> grid, profile, helix, dense; // in FlankTopology's order
  };
  const GrindingSetup& setup_;
  SimulationOptions options_;
  std::vector<FlankPlan> flanks_;
  std::vector<double> rows_, cols_, prof_xi_, helix_z_, dense_rows_, dense_cols_;
  double prof_z_ = 0.0, helix_xi_ = 0.0;
};

} // namespace geartopo::grinding
