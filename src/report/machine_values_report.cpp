#include "geartopo/report/machine_values_report.hpp"

namespace geartopo::report {

nlohmann::json machine_pitch_table_json(const workbench::MachinePitchComparison& c) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : c.rows)
    rows.push_back({{"tooth", r.tooth}, {"flank", geartopo::to_string(r.side)}, {"machine_fp_um", r.machine_fp_um},
                    {"geartopo_fp_um", r.geartopo_fp_um}, {"machine_Fp_um", r.machine_Fp_um},
                    {"geartopo_Fp_um", r.geartopo_Fp_um}, {"flagged", r.flagged}});
  return {{"rows", rows},
          {"max_abs_fp_difference_um", c.max_abs_fp_difference_um},
          {"max_abs_Fp_difference_um", c.max_abs_Fp_difference_um},
          {"flagged", c.flagged},
          {"flag_above_um", workbench::kMachineMismatchUm},
          {"likely_cause", c.likely_cause.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.likely_cause)}};
}

nlohmann::json machine_flank_values_json(const workbench::MachineFlankComparison& c,
                                         const measurement::KlingelnbergValues& m) {
  nlohmann::json rows = nlohmann::json::array(), quantities = nlohmann::json::array(), settings = nlohmann::json::object();
  for (const auto& r : c.rows)
    rows.push_back({{"tooth", r.tooth},
                    {"flank", geartopo::to_string(r.side)},
                    {"quantity", measurement::symbol(r.quantity)},
                    {"machine_um", r.machine_um},
                    {"geartopo_um", r.geartopo_um},
                    {"difference_um", r.machine_um - r.geartopo_um},
                    {r.quantity >= measurement::MachineQuantity::HelixSlope ? "helix_trace_diameter_mm" : "profile_trace_z_mm",
                     r.trace_position_mm},
                    {"flagged", r.flagged},
                    {"line", r.line}});
  for (const auto& q : c.quantities)
    quantities.push_back({{"quantity", measurement::symbol(q.quantity)},
                          {"rows", q.rows},
                          {"flagged", q.flagged},
                          {"max_abs_difference_um", q.max_abs_difference_um},
                          {"cause", q.flagged ? nlohmann::json(workbench::to_string(q.cause)) : nlohmann::json(nullptr)},
                          {"likely_cause", q.flagged ? nlohmann::json(q.likely_cause) : nlohmann::json(nullptr)}});
  for (const auto& [code, s] : m.settings) settings[std::to_string(code)] = s.text;
  return {{"file", m.source},           {"rows", rows},
          {"quantities", quantities},   {"flagged", c.flagged},
          {"flag_above_um", workbench::kMachineMismatchUm},
          {"not_compared", c.not_compared}, {"settings", settings},
          {"filters", m.filters},       {"unknown_lines", m.unknown_lines}};
}

} // namespace geartopo::report
