// geartopo — ISO 1328-1 evaluation of flank topologies (simulated or measured traces): the conversion into the
// evaluator's input, the iso1328.json sections and the printed table. Units: µm, mm.
#pragma once

#include "evaluation/gear_evaluation.hpp"
#include "gears/evaluation_ranges.hpp"
#include "gears/gear_geometry.hpp"
#include "grinding/topology.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace geartopo::app {

evaluation::GearParameters gear_parameters(const gears::GearGeometry& g);

/// Profile traces over L_α, helix traces over L_β, and for pitch and runout the deviation of each flank at mid face
/// width on the helix-trace diameter (the middle of L_α).
evaluation::GearMeasurement gear_measurement(const gears::GearGeometry& g, const gears::EvaluationRanges& r,
                                             const std::vector<grinding::FlankTopology>& topo);

struct IsoResult {
  evaluation::GearParameters parameters;
  evaluation::GearEvaluation evaluation;
};

IsoResult evaluate_iso(const gears::GearGeometry& g, const gears::EvaluationRanges& r,
                       const std::vector<grinding::FlankTopology>& topo);

/// One section of iso1328.json: per flank the six trace values, the flank's pitch and runout values and each value's
/// class; the gear's pitch and runout, the mean slopes, the class-5 tolerances and the overall class.
nlohmann::json iso_json(const IsoResult& r);
/// The class-5 tolerances (µm), or null when ISO 1328-1 does not apply to the gear.
nlohmann::json class5_tolerances_json(const evaluation::GearParameters& p);
std::string iso_table(const IsoResult& r);

} // namespace geartopo::app
