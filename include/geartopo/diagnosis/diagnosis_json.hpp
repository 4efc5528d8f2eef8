// geartopo — diagnosis.json and plan.json: a diagnosis as data, one writer for every front end (the CLI's `diagnose`,
// `plan`, `report`, `run`, and the Python module's dicts). Units in every key (µm, µrad, s, deg; unit-free ΔBIC).
#pragma once

#include "geartopo/diagnosis/diagnose.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace geartopo::diagnosis {

/// The unit of a parameter key: from its first unit token to the end ("wear_um_per_stroke" → "um_per_stroke",
/// "x_growth_um" → "um", "dressing_interval_strokes" → "strokes"); empty when it names none.
std::string unit_of_key(const std::string& key);
/// A decision record: {"reason", "subject", "names", "numbers": {key: value or [values]}, "unit"?, "test"?, "text"}.
nlohmann::json decision_json(const Decision& d);
/// One explanation: effect(s), parameters with value, uncertainty, unit, fitted; scores.
nlohmann::json candidate_json(const Candidate& c);
/// What to measure next: the competing explanations, the recommended teeth and every unmeasured tooth's separation.
nlohmann::json measurement_plan_json(const MeasurementPlan& plan);

/// diagnosis.json: set-up terms, every candidate, the chosen explanation, rivals, plan, assumed values, verdict.
/// `allowance_offset_um`: where the model's nominal flank sits (mean_allowance_offset_um).
nlohmann::json diagnosis_json(const std::string& scene, const std::string& measured, const Diagnosis& d,
                              double allowance_offset_um);

/// plan.json (`geartopo plan`): the chosen explanation, whether the diagnosis is ambiguous, its measurement plan
/// (measurement_plan_json; null when not ambiguous) and the verdict.
nlohmann::json plan_json(const std::string& scene, const std::string& measured, const Diagnosis& d);

} // namespace geartopo::diagnosis
