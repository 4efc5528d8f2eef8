// geartopo CLI — JSON of diagnosis results shared by `diagnose` and `plan` (docs/diagnosis.md): units in every key.
#pragma once

#include "geartopo/diagnosis/diagnose.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace geartopo::app {

/// The unit of a parameter key: from its first unit token to the end ("wear_um_per_stroke" → "um_per_stroke",
/// "x_growth_um" → "um", "dressing_interval_strokes" → "strokes"); empty when it names none.
std::string unit_of_key(const std::string& key);
/// One explanation: effect(s), parameters with value, uncertainty, unit, fitted; scores.
nlohmann::json candidate_json(const diagnosis::Candidate& c);
/// What to measure next: the competing explanations, the recommended teeth and every unmeasured tooth's separation.
nlohmann::json measurement_plan_json(const diagnosis::MeasurementPlan& plan);

} // namespace geartopo::app
