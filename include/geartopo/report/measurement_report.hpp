// geartopo — the files of a comparison and a diagnosis, one writer for every command that makes them (`compare`,
// `diagnose`, `plan`, `report`, `run`): compare.json, residuals.csv, diagnosis.json. Units in every key and column.
#pragma once

#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/measurement/measured_points.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace geartopo::report {

/// residuals.csv: one row per measured point, in the measurement's order —
/// tooth,flank,row,col,diameter_mm,z_mm,measured_um,model_um,residual_um,source_line,point_id
/// (row/col 0 when the file has no grid indices; source_line: the point's line in the measurement file; point_id: a
/// point cloud's id column, −1 when it has none). Written atomically.
void write_residuals_csv(const std::filesystem::path& file, const std::vector<measurement::MeasuredPoint>& points,
                         const diagnosis::Comparison& comparison);

/// What `geartopo compare` prints: the point counts, the residual's RMS and extreme overall and per flank (the numbers
/// of compare_json, rounded), where the model fails, the patterns and the tooth-to-tooth trends.
std::string compare_summary_text(const diagnosis::Comparison& comparison);

/// compare.json: statistics, patterns per flank, tooth-to-tooth trends, failing regions.
nlohmann::json compare_json(const std::string& scene, const std::string& measured,
                            const std::vector<measurement::MeasuredPoint>& points, const diagnosis::Comparison& comparison);

/// The unit of a parameter key: from its first unit token to the end ("wear_um_per_stroke" → "um_per_stroke",
/// "x_growth_um" → "um", "dressing_interval_strokes" → "strokes"); empty when it names none.
std::string unit_of_key(const std::string& key);
/// One explanation: effect(s), parameters with value, uncertainty, unit, fitted; scores.
nlohmann::json candidate_json(const diagnosis::Candidate& c);
/// What to measure next: the competing explanations, the recommended teeth and every unmeasured tooth's separation.
nlohmann::json measurement_plan_json(const diagnosis::MeasurementPlan& plan);

/// diagnosis.json: set-up terms, every candidate, the chosen explanation, rivals, plan, assumed values, verdict.
/// `allowance_offset_um`: where the model's nominal flank sits (diagnosis::mean_allowance_offset_um).
nlohmann::json diagnosis_json(const std::string& scene, const std::string& measured, const diagnosis::Diagnosis& d,
                              double allowance_offset_um);

/// plan.json (`geartopo plan`): the chosen explanation, whether the diagnosis is ambiguous, its measurement plan
/// (measurement_plan_json; null when not ambiguous) and the verdict.
nlohmann::json plan_json(const std::string& scene, const std::string& measured, const diagnosis::Diagnosis& d);

} // namespace geartopo::report
