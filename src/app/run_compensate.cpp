#include "app/compensate_command.hpp"

#include "app/commands.hpp"
#include "app/compensation_warnings.hpp"
#include "app/json_summary.hpp"
#include "app/messages.hpp"
#include "app/work_estimates.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/compensation/cycle_corrections.hpp"
#include "geartopo/compensation/isg_table.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/output_folder.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/report/improvement.hpp"
#include "geartopo/report/iso_report.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <optional>
#include <tuple>

namespace geartopo::app {
namespace {

std::pair<double, double> range_of(const std::vector<grinding::FlankTopology>& topo) {
  double lo = 1e300, hi = -1e300;
  for (const auto& ft : topo)
    for (const auto& p : ft.grid) lo = std::min(lo, p.deviation_um), hi = std::max(hi, p.deviation_um);
  return {lo, hi};
}

/// What the run reads and writes, checked before any work: no input and no file geartopo did not write is replaced.
output::RunFiles run_files(const CompensateOptions& opt, const pipeline::MonteCarloOptions& mc) {
  output::RunFiles files{{opt.scene},
                         {"corrections.csv", "cycle_corrections.csv", "topology_before.csv", "topology_after.csv",
                          "traces_before.csv", "traces_after.csv", "iso1328.json"}};
  if (opt.isg_table) files.outputs.emplace_back("isg_compensation.csv");
  if (mc.samples > 0) files.outputs.emplace_back("prediction_samples.csv");
  if (mc.samples > 0 && mc.shards == 1) files.outputs.insert(files.outputs.end(), {"prediction.json", "prediction.txt"});
  return files;
}

/// The gear before and after (the model corrected by itself), the corrections, and the cycle table with the gear
/// ground again with exactly that (docs/compensation.md): index and lead corrections per space, Y and A fixed. On a
/// chain none of whose linear axes can carry the stroke there is no cycle table, and no_cycle says why.
struct Compensation {
  std::vector<grinding::FlankTopology> before, after;
  compensation::CorrectionTable table;
  std::optional<compensation::CycleCorrections> cycle;
  double max_cycle = 0.0; ///< largest |deviation| with the cycle table, µm
  std::string no_cycle;   ///< the warning when there is no cycle table
};

/// The cycle form of the corrections and the largest |deviation| of the gear ground with exactly it (the after-state
/// of the cycle form is shown, not assumed); none, with the warning, when no axis can carry the stroke.
std::tuple<std::optional<compensation::CycleCorrections>, double, std::string>
cycle_form(const CompensateOptions& opt, const Workbench& wb, const grinding::SimulationOptions& so,
           const compensation::CorrectionTable& table) {
  std::optional<compensation::CycleCorrections> cycle;
  try {
    cycle = compensation::make_cycle_corrections(table, wb.setup.geometry().twist_rad_per_mm(), opt.lead_step);
  } catch (const compensation::NoStrokeAxis& e) {
    return {std::nullopt, 0.0, fmt::format("no cycle table (cycle_corrections.csv not written): {}", e.what())};
  }
  std::vector<compensation::CorrectionRow> cycle_rows = table.rows();
  for (auto& r : cycle_rows) r.correction = cycle->at(r);
  const compensation::CorrectionTable cycle_table(std::move(cycle_rows), table.axes());
  const compensation::CompensatedProcess cycle_corrected(wb.process(), cycle_table);
  const double max_cycle = grinding::largest_abs_deviation_um(grinding::simulate_topology(wb.setup, cycle_corrected, so));
  return {std::move(cycle), max_cycle, std::string()};
}

Compensation compensate(const CompensateOptions& opt, const Workbench& wb, const grinding::SimulationOptions& so) {
  compensation::CompensationOptions co;
  co.method = opt.method == "paper"   ? compensation::Method::Paper
              : opt.method == "cycle" ? compensation::Method::Cycle
                                      : compensation::Method::Flank;
  co.step_mm = opt.step;
  auto before = grinding::simulate_topology(wb.setup, wb.process(), so);
  auto table = compensation::compute_corrections(
      wb.setup, wb.process(), {wb.machine, wb.scene.machine.datum_face_z_mm, wb.scene.machine.chain}, co);
  const compensation::CompensatedProcess corrected(wb.process(), table);
  auto after = grinding::simulate_topology(wb.setup, corrected, so);
  auto [cycle, max_cycle, no_cycle] = cycle_form(opt, wb, so, table);
  return {std::move(before), std::move(after), std::move(table), std::move(cycle), max_cycle, std::move(no_cycle)};
}

/// The after-state as a distribution (docs/monte-carlo.md), computed by the driver: under MPI (geartopo-mpi) every
/// rank computes its shard and rank 0 gathers them; nullopt on the other ranks.
std::optional<pipeline::MonteCarloRun> predict(const CompensateOptions& opt, const Workbench& wb,
                                               const compensation::CorrectionTable& table,
                                               const pipeline::MonteCarloOptions& mc) {
  const MonteCarloDriver& driver = monte_carlo_driver();
  pipeline::MonteCarloOptions watched = driver.this_process(mc);
  MonteCarloWatch watch(driver.samples_on_this_process(watched), watched.threads, opt.mc.max_time_s, driver.split_hint(),
                        mc.adaptive_tolerance_um > 0.0);
  watched.on_sample_done = watch.callback();
  watched.on_prepared = [&watch] { watch.prepared(); };
  auto run = driver.run(wb, table, watched);
  if (!run) return run;
  // What `merge` checks that every shard shares: the scene, its tables and the settings behind the corrections.
  run->scene_fingerprint = pipeline::scene_fingerprint(wb, fmt::format("method={} step_mm={}", opt.method, opt.step));
  run->gear = pipeline::gear_record(wb.setup.geometry().spec()); // also when rank 0 gathered the samples as numbers
  return run;
}

/// iso1328.json's record of the compensation: its method and table, the cycle table and what it leaves.
nlohmann::json compensation_json(const CompensateOptions& opt, const Compensation& c) {
  const auto cmax = c.table.max_abs();
  nlohmann::json j;
  j["compensation"] = {{"method", opt.method},
                       {"rows", c.table.rows().size()},
                       {"rows_outside_strokes", c.table.rows_outside_strokes()},
                       {"max_correction", {{"dX_um", units::um_from_mm(cmax(0))}, {"dY_um", units::um_from_mm(cmax(1))},
                                           {"dZ_um", units::um_from_mm(cmax(2))}, {"dA_urad", units::urad_from_rad(cmax(3))},
                                           {"dC_urad", units::urad_from_rad(cmax(4))}}}};
  if (!c.cycle) {
    j["cycle"] = {{"file", nullptr}, {"not_written", c.no_cycle}};
    return j;
  }
  // The set-up axis' and the swivel's letters are the chain's (Y and A on the CFXZAY).
  const std::string& y = c.cycle->axis_names[static_cast<size_t>(c.cycle->setup_slot)];
  const std::string& a = c.cycle->axis_names[3];
  j["cycle"] = {{"file", "cycle_corrections.csv"},
                {"lead_step_mm", opt.lead_step},
                {"setup_d" + y + "_um", units::um_from_mm(c.cycle->setup_dY_mm)},
                {"setup_d" + a + "_urad", units::urad_from_rad(c.cycle->setup_dA_rad)},
                {"not_carried_" + y + "_um", units::um_from_mm(c.cycle->y_not_carried_mm)},
                {"not_carried_" + a + "_urad", units::urad_from_rad(c.cycle->a_not_carried_rad)},
                {"nominal_largest_abs_deviation_after_um", c.max_cycle}};
  if (!c.cycle->chain.empty())
    j["cycle"]["axes"] = {{"stroke", c.cycle->axis_names[static_cast<size_t>(c.cycle->stroke_slot)]},
                          {"lead", c.cycle->axis_names[static_cast<size_t>(c.cycle->lead_slot)]},
                          {"setup", y}};
  return j;
}

/// Writes isg_compensation.csv and says what the position-only table leaves: the machine's geometric errors with the
/// wheel centre put back (the drawing's helix motions still run). Returns the JSON record and the printed summary.
std::pair<nlohmann::json, std::string> write_isg(const CompensateOptions& opt, const Workbench& wb,
                                                 const compensation::IsgTable& isg, const compensation::IsgOptions& options,
                                                 const grinding::SimulationOptions& so) {
  compensation::write_isg_table(std::filesystem::path(opt.out) / "isg_compensation.csv", isg, options.limits);
  const compensation::PositionCompensatedProcess position_only(wb.machine_process, Eigen::Vector3d::Zero());
  const workbench::WithDesignMotion designed(wb, position_only);
  const auto left = grinding::simulate_topology(wb.setup, designed.process(), so);
  const auto iso_left = workbench::evaluate_iso(wb.setup.geometry(), wb.setup.ranges(), left, opt.iso);
  const double max_left = grinding::largest_abs_deviation_um(left);
  nlohmann::json left_json = {{"largest_abs_deviation_um", max_left}};
  std::string summary = fmt::format("left after the table: largest |dev| {:.2f} µm", max_left);
  for (const auto& q : iso_left.evaluation.classification.quantities) {
    left_json[std::string(evaluation::symbol(q.quantity))] = q.worst_value_um;
    summary += fmt::format(", {} {:.2f} µm", evaluation::symbol(q.quantity), q.worst_value_um);
  }
  nlohmann::json j = {{"file", "isg_compensation.csv"},
                      {"records", isg.records()},
                      {"max_records", options.limits.max_records},
                      {"tool_centre_point", "wheel centre"},
                      {"scope", "geometric machine errors only (the scene's effects are not in the table)"},
                      {"nominal_left_after_table", left_json}};
  return {std::move(j), std::move(summary)};
}

/// The text summary: corrections, topology, cycle table, the prediction and improvement or the nominal table.
void print_compensation(const CompensateOptions& opt, const Compensation& c, const workbench::IsoResult& iso_b,
                   const workbench::IsoResult& iso_a, const std::optional<pipeline::MonteCarloSummary>& prediction,
                   const grinding::SimulationOptions& so) {
  const auto cmax = c.table.max_abs();
  const auto [lb, hb] = range_of(c.before);
  const auto [la, ha] = range_of(c.after);
  std::cout << fmt::format("Compensation ({} method), {} path samples every {} mm, {} outside the strokes\n", opt.method,
                           c.table.rows().size(), opt.step, c.table.rows_outside_strokes());
  std::cout << fmt::format("  largest corrections: X {:.2f} µm, Y {:.2f} µm, Z {:.2f} µm, A {:.2f} µrad, C {:.2f} µrad\n",
                           units::um_from_mm(cmax(0)), units::um_from_mm(cmax(1)), units::um_from_mm(cmax(2)),
                           units::urad_from_rad(cmax(3)), units::urad_from_rad(cmax(4)));
  std::cout << fmt::format("  topology (all teeth, {}×{} grid): before {:.2f} … {:.2f} µm; {}: {:.2f} … {:.2f} µm\n", so.rows,
                           so.cols, lb, hb, report::kNominalLabel, la, ha);
  if (!prediction)
    std::cout << fmt::format("  largest |deviation|: {:.2f} µm before; {}: {:.2f} µm (no prediction: --samples 0 or "
                             "a shard, so no improvement figure)\n",
                             grinding::largest_abs_deviation_um(c.before), report::kNominalLabel,
                             grinding::largest_abs_deviation_um(c.after));
  if (c.cycle) {
    const std::string& y = c.cycle->axis_names[static_cast<size_t>(c.cycle->setup_slot)];
    const std::string& a = c.cycle->axis_names[3];
    std::cout << fmt::format("  with the cycle table (index + lead per space, {} {:+.2f} µm and {} {:+.2f} µrad per gear; "
                             "not carried: {} {:.2f} µm, {} {:.2f} µrad): largest |deviation| {:.2f} µm, {}\n",
                             y, units::um_from_mm(c.cycle->setup_dY_mm), a, units::urad_from_rad(c.cycle->setup_dA_rad), y,
                             units::um_from_mm(c.cycle->y_not_carried_mm), a,
                             units::urad_from_rad(c.cycle->a_not_carried_rad), c.max_cycle, report::kNominalLabel);
  } else {
    std::cout << "  no cycle table: see the warning\n";
  }
  if (prediction) {
    for (const auto& l : report::prediction_lines(*prediction)) std::cout << "  " << l << "\n";
    for (const auto& l : report::improvement_lines(*prediction)) std::cout << "  " << l << "\n";
    return;
  }
  // Without a prediction the nominal after-state is shown as what it is (the model compensating itself), with no
  // "% better": that would be a tautology.
  const auto& qb = iso_b.evaluation.classification.quantities;
  const auto& qa = iso_a.evaluation.classification.quantities;
  std::cout << fmt::format("  {:<6} {:>10} {:>10}  {:>6} {:>6}   (nominal: the model corrected by itself, ≈ 0 by "
                           "construction; not a result)\n", "ISO", "before", "nominal", "class", "");
  for (size_t i = 0; i < qb.size() && i < qa.size(); ++i)
    std::cout << fmt::format("  {:<6} {:>10.2f} {:>10.2f}  {:>6} → {}\n", evaluation::symbol(qb[i].quantity),
                             qb[i].worst_value_um, qa[i].worst_value_um, evaluation::class_label(qb[i].flank_class),
                             evaluation::class_label(qa[i].flank_class));
  const auto& cb = iso_b.evaluation.classification;
  const auto& ca = iso_a.evaluation.classification;
  if (cb.overall && ca.overall)
    std::cout << fmt::format("  overall flank tolerance class: {} before; {}: {}\n", evaluation::class_label(*cb.overall),
                             report::kNominalLabel, evaluation::class_label(*ca.overall));
}

} // namespace

int run_compensate(const CompensateOptions& opt) {
  JsonSummary json(opt.json);
  pipeline::MonteCarloOptions mc = monte_carlo_options(opt.mc); // bad --shard: usage error before any work
  mc.iso = opt.iso; // the samples evaluated as the nominal gears are (and prediction.json records it)
  const output::RunFiles files = run_files(opt, mc);
  output::check_run_files(opt.out, files);
  // The writer opens its folder (and takes its lock) before the work; under MPI the other ranks write nothing.
  const std::filesystem::path out(opt.out);
  std::optional<output::OutputFolder> folder;
  if (mc.samples == 0 || monte_carlo_driver().writes_outputs()) folder.emplace(out, files);
  const Workbench wb(opt.scene);
  refuse_paper_on_a_designed_helix(opt.method, wb);
  const auto& g = wb.setup.geometry();
  grinding::SimulationOptions so;
  so.profile_points = wb.scene.grid.profile_points;
  so.helix_points = wb.scene.grid.helix_points;
  so.rows = wb.scene.grid.rows;
  so.cols = wb.scene.grid.cols;

  // ISG table first: a table the controller would refuse stops the command before any file is written.
  std::optional<compensation::IsgTable> isg;
  compensation::IsgOptions isg_options;
  isg_options.limits.max_records = opt.isg_max_records;
  if (opt.isg_table) {
    isg = compensation::make_isg_table(wb.machine, *wb.scene.machine.chain, isg_options);
    compensation::check_isg_table(*isg, isg_options.limits);
  }
  const Compensation c = compensate(opt, wb, so);
  // The prediction before any file is written: one refused by its work estimate (--max-time-s) leaves the output
  // folder as it was.
  std::optional<pipeline::MonteCarloRun> mc_run;
  if (mc.samples > 0) {
    mc_run = predict(opt, wb, c.table, mc);
    if (!mc_run) return 0; // an MPI rank other than 0: its samples are on rank 0, which writes the files
  }

  c.table.write_csv(out / "corrections.csv");
  if (c.cycle) c.cycle->write_csv(out / "cycle_corrections.csv");
  grinding::write_topology_csv(out / "topology_before.csv", c.before);
  grinding::write_topology_csv(out / "topology_after.csv", c.after);
  grinding::write_traces_csv(out / "traces_before.csv", c.before);
  grinding::write_traces_csv(out / "traces_after.csv", c.after);

  const workbench::IsoResult iso_b = workbench::evaluate_iso(g, wb.setup.ranges(), c.before, opt.iso);
  const workbench::IsoResult iso_a = workbench::evaluate_iso(g, wb.setup.ranges(), c.after, opt.iso);
  const double max_b = grinding::largest_abs_deviation_um(c.before), max_a = grinding::largest_abs_deviation_um(c.after);
  nlohmann::json j;
  j["scene"] = wb.scene.name;
  j["units"] = "µm; plus material positive; profile/helix values in the direction each section names (iso_direction)";
  j["before"] = report::iso_json(iso_b);
  // The nominal after-state is the model corrected by itself (≈ 0 by construction): kept under a name that says so,
  // never `after`; what the machine would grind is `prediction`, and `improvement` comes from it alone.
  j["nominal_after"] = report::iso_json(iso_a);
  j["nominal_after_meaning"] = report::kNominalAfterMeaning;
  j["largest_abs_deviation_um"] = {{"before", max_b}, {"nominal_after", max_a}};
  j.update(compensation_json(opt, c));
  std::string isg_summary;
  if (isg) std::tie(j["isg_table"], isg_summary) = write_isg(opt, wb, *isg, isg_options, so);
  j["warnings"] = nlohmann::json::array();
  add_warning(j, compensation_made_worse(max_b, max_a));
  add_warning(j, c.no_cycle);
  // The nominal `after` is the model compensating itself (≈ 0 by construction); the prediction grinds with a machine
  // drawn within the scene's uncertainties.
  std::optional<pipeline::MonteCarloSummary> prediction;
  if (mc_run) {
    pipeline::write_run_csv(out / "prediction_samples.csv", *mc_run);
    if (mc.shards == 1) {
      prediction = pipeline::summarise(*mc_run);
      write_prediction(out, *prediction);
      j["prediction"] = report::prediction_json(*prediction);
      j["improvement"] = report::improvement_json(*prediction);
      add_warning(j, prediction_made_worse(*prediction));
    }
  }
  // An error-free machine's numbers come from nothing but the defaults: said before them, and in the file.
  const std::string note = error_free_machine_note(wb);
  if (!note.empty()) j["notes"].push_back(note);
  output::write_text_atomically(out / "iso1328.json", j.dump(2) + "\n");

  if (!note.empty()) std::cout << note << "\n";
  print_compensation(opt, c, iso_b, iso_a, prediction, so);
  if (isg)
    std::cout << fmt::format("  ISG volumetric table (isg_compensation.csv, {} records; corrects the wheel position, "
                             "not its orientation): {}\n",
                             isg->records(), isg_summary);
  std::cout << "wrote " << out.string() << "/corrections.csv, " << (c.cycle ? "cycle_corrections.csv, " : "")
            << "topology_before.csv, "
            << "topology_after.csv, iso1328.json" << (isg ? ", isg_compensation.csv" : "")
            << (mc.samples > 0 ? ", prediction_samples.csv" : "") << (prediction ? ", prediction.json, prediction.txt" : "")
            << "\n";
  finish_output_folder(*folder);
  json.emit(j);
  return 0;
}

} // namespace geartopo::app
