// geartopo — flank topologies (simulated or measured traces) as the ISO 1328-1 evaluator's input, and their
// evaluation: profile traces over L_α, helix traces over L_β, and for pitch and runout the deviation of each flank at
// mid face width on the helix-trace diameter (the middle of L_α). Units: µm, mm.
#pragma once

#include "geartopo/evaluation/gear_evaluation.hpp"
#include "geartopo/evaluation/tolerances.hpp"
#include "geartopo/gears/evaluation_ranges.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/grinding/topology.hpp"

#include <vector>

namespace geartopo::workbench {

evaluation::GearParameters gear_parameters(const gears::GearGeometry& g);

evaluation::GearMeasurement gear_measurement(const gears::GearGeometry& g, const gears::EvaluationRanges& r,
                                             const std::vector<grinding::FlankTopology>& topo);

struct IsoResult {
  evaluation::GearParameters parameters;
  evaluation::GearEvaluation evaluation;
};

IsoResult evaluate_iso(const gears::GearGeometry& g, const gears::EvaluationRanges& r,
                       const std::vector<grinding::FlankTopology>& topo);

} // namespace geartopo::workbench
