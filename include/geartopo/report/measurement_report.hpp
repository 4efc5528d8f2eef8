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

} // namespace geartopo::report
