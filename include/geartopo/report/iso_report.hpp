// geartopo — ISO 1328-1 evaluation of flank topologies (simulated or measured traces): the conversion into the
// evaluator's input, the iso1328.json sections and the printed table. Units: µm, mm.
#pragma once

#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/evaluation/gear_evaluation.hpp"
#include "geartopo/gears/evaluation_ranges.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/grinding/topology.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace geartopo::report {

// The conversion and evaluation live in the diagnosis library (the benchmarks use them too).
using workbench::evaluate_iso;
using workbench::gear_measurement;
using workbench::gear_parameters;
using workbench::IsoResult;

/// One section of iso1328.json: per flank the six trace values, the flank's pitch and runout values and each value's
/// class; the gear's pitch and runout, the mean slopes, the class-5 tolerances and the overall class.
nlohmann::json iso_json(const IsoResult& r);
/// The class-5 tolerances (µm), or null when ISO 1328-1 does not apply to the gear.
nlohmann::json class5_tolerances_json(const evaluation::GearParameters& p);
std::string iso_table(const IsoResult& r);

} // namespace geartopo::report
