#include "app/evaluate_command.hpp"

#include "app/commands.hpp"
#include "app/messages.hpp"
#include "app/series_command.hpp"

#include "geartopo/commands/machine_values.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/output_folder.hpp"
#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/measurement/klingelnberg_values.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/report/iso_report.hpp"
#include "geartopo/report/machine_values_report.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/workbench/machine_flank_values.hpp"
#include "geartopo/workbench/machine_pitch.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>

namespace geartopo::app {
namespace {

/// A value as printed with 3 decimals: one that rounds to zero is +0, so the table says 0.000, never -0.000.
double printed_3(double v) { return std::abs(v) < 5e-4 ? 0.0 : v; }

std::string machine_flank_values_text(const workbench::MachineFlankComparison& c, const measurement::KlingelnbergValues& m) {
  std::string out = fmt::format("The machine's values ({}) beside geartopo's evaluation of the same traces, µm "
                                "(profile trace nearest mid face width at z, helix trace nearest mid profile at d):\n",
                                m.source);
  out += "  tooth flank  quantity   machine  geartopo  difference  trace\n";
  for (const auto& r : c.rows)
    out += fmt::format("  {:5} {:6} {:8} {:9.3f} {:9.3f} {:11.3f}  {}= {:.3f} mm{}\n", r.tooth, geartopo::to_string(r.side),
                       measurement::symbol(r.quantity), printed_3(r.machine_um), printed_3(r.geartopo_um),
                       printed_3(r.machine_um - r.geartopo_um),
                       r.quantity >= measurement::MachineQuantity::HelixSlope ? "d" : "z", r.trace_position_mm,
                       r.flagged ? "  ← flagged" : "");
  for (const auto& q : c.quantities)
    out += fmt::format("  {}: {} values, max |difference| {:.3f} µm, {} above {:.1f} µm{}\n", measurement::symbol(q.quantity),
                       q.rows, q.max_abs_difference_um, q.flagged, workbench::kMachineMismatchUm,
                       q.flagged ? " — likely cause: " + q.likely_cause : "");
  for (const auto& n : c.not_compared) out += "  not compared: " + n + "\n";
  return out;
}

/// --prediction, read before anything is written (a wrong prediction file leaves the output folder as it was) and
/// refused when it predicts another gear (z, module, angles, shift, width), naming both.
pipeline::MonteCarloSummary read_prediction_of(const EvaluateOptions& opt, const Workbench& wb) {
  auto prediction = report::read_prediction_json(opt.prediction);
  const std::string gear = pipeline::gear_record(wb.setup.geometry().spec());
  if (prediction.gear.empty())
    throw InputError(opt.prediction, 0, 0, "gear",
                     "does not record the gear it predicts (written before geartopo recorded it), so it cannot be "
                     "shown to be of this scene's gear: predict again with geartopo compensate");
  if (prediction.gear != gear)
    throw InputError(opt.prediction, 0, 0, "gear",
                     fmt::format("a prediction of another gear ({}); {} is {}", prediction.gear, opt.prediction, gear));
  return prediction;
}

/// The ISO options the measurement is evaluated with: the prediction's (prediction.json "iso_options"), as its samples
/// were; a flag that says otherwise would compare values of another convention. A file without the key: the flags.
workbench::IsoOptions iso_options_of(const EvaluateOptions& opt, const std::optional<pipeline::MonteCarloSummary>& prediction) {
  if (!prediction || !prediction->iso) return opt.iso;
  const auto& recorded = *prediction->iso;
  if (opt.iso_direction_given && opt.iso.direction != recorded.direction)
    throw CLI::ValidationError("--iso-direction", fmt::format("{}, but {} was predicted with {}: leave the flag out or "
                                                              "predict again",
                                                              evaluation::to_string(opt.iso.direction), opt.prediction,
                                                              evaluation::to_string(recorded.direction)));
  if (opt.helix_slope_sign_given && opt.iso.helix_slope_sign != recorded.helix_slope_sign)
    throw CLI::ValidationError("--helix-slope-sign",
                               fmt::format("{}, but {} was predicted with {}: leave the flag out or predict again",
                                           evaluation::to_string(opt.iso.helix_slope_sign), opt.prediction,
                                           evaluation::to_string(recorded.helix_slope_sign)));
  return recorded;
}

/// The flanks evaluated: measured traces (--traces) or the simulated gear, and, for an export, what the measuring
/// machine evaluated itself (commands::read_traces_with_machine_values).
struct Flanks {
  std::vector<grinding::FlankTopology> topo;
  std::string source;
  std::optional<commands::TracesWithMachineValues> measured; // --traces: the traces, the export, the value file
};

Flanks measured_flanks(const EvaluateOptions& opt, const Workbench& wb) {
  Flanks f;
  refuse_mka_flags_without_export(opt.traces, opt.mka);
  auto read = commands::read_traces_with_machine_values(wb, opt.traces, opt.machine_values, opt.mka.options,
                                                        {"--machine-values", "--machine-values {}"}, opt.mka.against);
  for (const auto& w : read.warnings) say("geartopo: warning: " + w);
  f.topo = read.traces.flanks;
  f.source = (read.traces.klingelnberg ? "measured traces (Klingelnberg export) " : "measured traces ") + opt.traces;
  f.measured = std::move(read);
  return f;
}

Flanks simulated_flanks(const EvaluateOptions& opt, const Workbench& wb) {
  Flanks f;
  grinding::SimulationOptions so;
  so.method = opt.method == "linear" ? grinding::Method::Linear : grinding::Method::Exact;
  so.profile_points = wb.scene.grid.profile_points;
  so.helix_points = wb.scene.grid.helix_points;
  f.topo = grinding::simulate_topology(wb.setup, wb.process(), so); // pitch and runout need every tooth
  f.source = "simulation (" + opt.method + ")";
  return f;
}

} // namespace

int run_evaluate(const EvaluateOptions& opt) {
  if (!opt.before_traces.empty() && (opt.prediction.empty() || opt.traces.empty() || opt.side != "after"))
    throw CLI::ValidationError("--before-traces", "needs --prediction and --traces (gear 2, the after side): gear 1's "
                                                  "traces are checked against the prediction's before band");
  if (opt.mka.against != measurement::MeasuredAgainst::as_file && opt.traces.empty())
    throw CLI::ValidationError("--measured-against", "needs --traces: it says what measured traces without a design_um "
                                                     "column are measured from");
  std::vector<std::filesystem::path> outputs{"iso1328.json"};
  if (!opt.prediction.empty()) outputs.push_back("against_prediction.png");
  const output::RunFiles files{{opt.scene, opt.traces, opt.machine_values, opt.prediction, opt.before_traces}, outputs};
  output::OutputFolder folder(opt.out, files); // locked and staged before any work: a second run is refused now
  const Workbench wb(opt.scene);
  std::optional<pipeline::MonteCarloSummary> prediction;
  if (!opt.prediction.empty()) prediction = read_prediction_of(opt, wb);
  const workbench::IsoOptions iso_options = iso_options_of(opt, prediction);
  if (!opt.machine_values.empty() && opt.traces.empty())
    throw CLI::ValidationError("--machine-values", "needs --traces EXPORT.mka: the values are compared with "
                                                   "geartopo's evaluation of the export's traces");
  const Flanks f = opt.traces.empty() ? simulated_flanks(opt, wb) : measured_flanks(opt, wb);
  const auto& g = wb.setup.geometry();
  const workbench::IsoResult iso = f.measured
                                       ? commands::evaluate_measured_traces(wb, f.measured->traces, opt.traces, iso_options)
                                       : workbench::evaluate_iso(g, wb.setup.ranges(), f.topo, iso_options);
  nlohmann::json j;
  j["scene"] = wb.scene.name;
  j["source"] = f.source;
  j["units"] = "µm; plus material positive";
  j["iso_direction"] = std::string(evaluation::to_string(iso_options.direction));
  j["before"] = report::iso_json(iso);
  std::optional<commands::MachineValuesResult> machine; // the export's pitch table and value file beside geartopo's
  if (f.measured) {
    machine = commands::machine_values(wb, *f.measured, iso);
    for (const auto& [key, value] : machine->json.items()) j[key] = value;
  }
  // The quantities as the prediction names them; largest |deviation| needs the grid (none in a traces file).
  std::vector<report::PredictionCheck> checks;
  if (prediction) {
    bool has_grid = false;
    for (const auto& ft : f.topo) has_grid = has_grid || !ft.grid.empty();
    checks = report::check_against_prediction(pipeline::gear_quantities(iso, f.topo), *prediction, opt.side, has_grid);
    j["against_prediction"] = report::prediction_check_json(checks, *prediction, opt.side);
    j["against_prediction"]["file"] = opt.prediction;
  }
  // Gear 1, ground without the corrections, against the before band: the error falling from gear 1 to gear 2.
  std::vector<report::PredictionCheck> gear1_checks;
  if (!opt.before_traces.empty()) {
    auto gear1 = measurement::read_any_traces(opt.before_traces, wb.setup, opt.mka.options, opt.mka.against);
    for (const auto& w : gear1.warnings) say("geartopo: warning: " + w);
    const auto iso1 = commands::evaluate_measured_traces(wb, gear1, opt.before_traces, iso_options);
    gear1_checks = report::check_against_prediction(pipeline::gear_quantities(iso1, gear1.flanks), *prediction, "before", false);
    j["before_against_prediction"] = report::prediction_check_json(gear1_checks, *prediction, "before");
    j["before_against_prediction"]["traces"] = opt.before_traces;
  }
  if (prediction)
    report::prediction_check_figure(*prediction, opt.side == "before" ? checks : gear1_checks,
                                    opt.side == "after" ? checks : std::vector<report::PredictionCheck>{},
                                    std::filesystem::path(opt.out) / "against_prediction.png");
  const std::filesystem::path out(opt.out);
  output::write_text_atomically(out / "iso1328.json", j.dump(2) + "\n");
  std::cout << "Source: " << f.source << "\n" << report::iso_table(iso);
  if (machine && machine->pitch) {
    const auto& beside = machine->pitch;
    if (beside->rows.empty())
      std::cout << "The export's pitch table: not compared (geartopo evaluates pitch only with every tooth of a side)\n";
    else
      std::cout << fmt::format("The export's pitch table beside geartopo's evaluation of the same traces ({} rows): "
                               "max |Δf_p| {:.2f} µm, max |ΔF_p| {:.2f} µm; {} rows differ by more than {:.1f} µm{}\n",
                               beside->rows.size(), beside->max_abs_fp_difference_um, beside->max_abs_Fp_difference_um,
                               beside->flagged, workbench::kMachineMismatchUm,
                               beside->likely_cause.empty() ? "" : " — likely cause: " + beside->likely_cause);
  }
  if (machine && machine->flank_values)
    std::cout << machine_flank_values_text(*machine->flank_values, *f.measured->machine_values);
  if (prediction) {
    std::cout << "Against " << opt.prediction << ":\n";
    for (const auto& l : report::prediction_check_lines(checks, *prediction, opt.side)) std::cout << "  " << l << "\n";
  }
  if (!gear1_checks.empty()) {
    std::cout << "Gear 1 (" << opt.before_traces << ", without the corrections) against the before band:\n";
    for (const auto& l : report::prediction_check_lines(gear1_checks, *prediction, "before")) std::cout << "  " << l << "\n";
  }
  std::cout << "wrote " << (out / "iso1328.json").string() << (prediction ? " and against_prediction.png" : "") << "\n";
  if (!opt.aqdef.empty()) {
    const auto part = series::iso_aqdef({{&iso.evaluation, std::nullopt, ""}}, iso.parameters, wb.scene.report.tolerance_class,
                                        aqdef_header(wb, "", ""));
    aqdef::write_dfq(opt.aqdef, part);
    std::cout << "wrote " << opt.aqdef << "\n";
  }
  finish_output_folder(folder);
  return 0;
}

} // namespace geartopo::app
