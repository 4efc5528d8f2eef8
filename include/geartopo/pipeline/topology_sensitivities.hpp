// geartopo — a gear's topology to first order in what a Monte Carlo sample draws of the machine (docs/monte-carlo.md,
// "Linear samples"): the exact topology of the nominal machine grinding with a correction table, plus the first-order
// change of every point's deviation per drawn quantity,
//   d(p) = d₀(p) + Σ_c J_map(p, c)·z_c + J_stroke(p, ·)·δq_s(p)                                        (µm)
// z_c the standard normal draw of map component c (its standard uncertainty u_c, or u_c(position) from the table's u
// column: ErrorSource::drawn), δq_s(p) the command offset (X, Y, Z mm; A, C rad) of the stroke that grinds p. The
// sensitivities are the project's first-order model at each point's generating pose (grinding::linear_deviation_mm:
// n·(δp + δθ × P)): the map's through the machine's first-order error Jacobian J_twistw_e (machine/first_order.hpp)
// moved to the gear's datum as MachineProcess does, the strokes' through the ideal axis Jacobian J_twistw_q as
// CompensatedProcess adds a correction. (The effects' uncertain values are not linear in the draw — a time constant —
// and are evaluated per sample: diagnosis::EffectContribution, pipeline/sample_model.cpp.) Checked against the exact
// simulation by finite differences (tests/pipeline/test_linear_samples.cpp).
// Units: µm per unit draw; per mm or rad of a stroke offset.
#pragma once

#include "geartopo/compensation/correction_table.hpp"
#include "geartopo/grinding/topology_plan.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <Eigen/Dense>

#include <vector>

namespace geartopo::pipeline {

/// An effect value with a standard uncertainty (Scene::effect_uncertainties), in the order the Monte Carlo draws them.
/// After the effects' values come the uncertain sizes of the scene's machine_changes (`change` true, `effect` the
/// index into Scene::machine_changes; only those with an uncertainty, so a scene without them draws as before).
struct UncertainEffectValue {
  size_t effect = 0, value = 0; ///< indices into Scene::effects and its values (a change: into machine_changes, 0)
  double u = 0.0;               ///< standard uncertainty (file units)
  double lo = 0.0, hi = 0.0;    ///< the effect's allowed range: a draw is held inside it
  bool change = false;          ///< a machine change's size (file units of its law's key)
};
std::vector<UncertainEffectValue> uncertain_effect_values(const scene::Scene& scene);

struct TopologySensitivities {
  Eigen::VectorXd nominal_um;  ///< N: the exact topology of the nominal scene (map, effects) with the table, flattened
  Eigen::MatrixXd map_um;      ///< N × 43: per unit standard normal draw of each component (scaled by its u)
  Eigen::MatrixXd stroke_um;   ///< N × 5: per mm (X, Y, Z) or rad (A, C) of the command offset of the point's stroke
  std::vector<int> space;      ///< N: the space whose stroke grinds the point
};

/// The sensitivities of the gear the scene's nominal machine grinds with `table` (a zero table: uncorrected) at the
/// points of `plan` (flattened in TopologyPlan::linear_contacts' order). `component_u` and the tables' u columns
/// scale map_um (MachineUncertainty::component_u). Runs on `threads` threads; the result does not depend on them.
TopologySensitivities topology_sensitivities(const workbench::Workbench& wb, const grinding::TopologyPlan& plan,
                                             const compensation::CorrectionTable& table, int threads);

/// The deviations of a topology flattened in TopologyPlan::linear_contacts' order (µm).
Eigen::VectorXd flatten_deviations(const std::vector<grinding::FlankTopology>& topo);
/// `topo` with its deviations replaced by `deviation_um` (same order as flatten_deviations).
void set_deviations(std::vector<grinding::FlankTopology>& topo, const Eigen::VectorXd& deviation_um);

} // namespace geartopo::pipeline
