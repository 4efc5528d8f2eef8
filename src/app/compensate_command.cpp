#include "app/commands.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/report/iso_report.hpp"
#include "geartopo/core/units.hpp"
#include "app/options.hpp"
#include "app/monte_carlo_flags.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/report/improvement.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/compensation/cycle_corrections.hpp"
#include "geartopo/compensation/isg_table.hpp"
#include "geartopo/grinding/topology_csv.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>

namespace geartopo::app {
namespace {

std::pair<double, double> range_of(const std::vector<grinding::FlankTopology>& topo) {
  double lo = 1e300, hi = -1e300;
  for (const auto& ft : topo)
    for (const auto& p : ft.grid) lo = std::min(lo, p.deviation_um), hi = std::max(hi, p.deviation_um);
  return {lo, hi};
}

} // namespace

void register_compensate_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, out, method = "flank";
    double step = 2.0;
    double lead_step = 5.0;
    bool isg_table = false;      // issue 15: the machine's errors as an ISG/TF5280 volumetric table
    int isg_max_records = 2000;
    workbench::IsoOptions iso;
    MonteCarloFlags mc;
    bool json = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("compensate", "Axis corrections along the wheel path (paper: Jacobian pseudo-inverse; "
                                                   "flank: minimise flank deviations) and the gear before/after");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML)")->required();
  cmd->add_option("--out", opt->out,
                  "Output directory (created): corrections.csv, cycle_corrections.csv, topology_before/after.csv, iso1328.json")
      ->required()
      ->check(non_empty_path());
  cmd->add_option("--method", opt->method,
                  "paper, flank (default; every axis at every pose) or cycle (X, Z, C per pose; Y and A per gear)")
      ->check(CLI::IsMember({"paper", "flank", "cycle"}));
  cmd->add_option("--step", opt->step, "Correction table spacing along each stroke, mm (default 2)")
      ->check(finite_in(0.05, 50.0));
  cmd->add_option("--lead-step", opt->lead_step,
                  "Largest Z step of the cycle table's lead corrections (cycle_corrections.csv), mm (default 5)")
      ->check(finite_in(0.1, 100.0));
  cmd->add_flag("--isg-table", opt->isg_table,
                "Also write isg_compensation.csv: the machine's error components as an ISG/Beckhoff TF5280 volumetric "
                "compensation table (ISO 230-1 names, mm/rad), and report the flank deviation it leaves (orientation)");
  cmd->add_option("--isg-max-records", opt->isg_max_records,
                  "The controller's vol_comp[i].max_records for --isg-table (default 2000)")
      ->check(CLI::Range(2, 1000000));
  add_iso_options(cmd, opt->iso);
  add_monte_carlo_options(cmd, opt->mc, true);
  cmd->add_flag("--json", opt->json, "Print iso1328.json's content (before, after, prediction, warnings) on stdout instead of the text");
  cmd->callback([&action, opt] {
    action = [opt] {
      JsonSummary json(opt->json);
      pipeline::MonteCarloOptions mc = monte_carlo_options(opt->mc); // bad --shard: usage error before any work
      mc.iso = opt->iso; // the samples evaluated as the nominal gears are (and prediction.json records it)
      // What the run writes, checked before any work: no input and no file geartopo did not write is replaced.
      output::RunFiles files{{opt->scene},
                             {"corrections.csv", "cycle_corrections.csv", "topology_before.csv", "topology_after.csv",
                              "traces_before.csv", "traces_after.csv", "iso1328.json"}};
      if (opt->isg_table) files.outputs.emplace_back("isg_compensation.csv");
      if (mc.samples > 0) files.outputs.emplace_back("prediction_samples.csv");
      if (mc.samples > 0 && mc.shards == 1) files.outputs.insert(files.outputs.end(), {"prediction.json", "prediction.txt"});
      output::check_run_files(opt->out, files);
      // The writer opens its folder (and takes its lock) before the work; under MPI the other ranks write nothing.
      const std::filesystem::path out(opt->out);
      std::optional<output::OutputFolder> folder;
      if (mc.samples == 0 || monte_carlo_driver().writes_outputs()) folder.emplace(out, files);
      const Workbench wb(opt->scene);
      refuse_paper_on_a_designed_helix(opt->method, wb);
      const auto& g = wb.setup.geometry();
      grinding::SimulationOptions so;
      so.profile_points = wb.scene.grid.profile_points;
      so.helix_points = wb.scene.grid.helix_points;
      so.rows = wb.scene.grid.rows;
      so.cols = wb.scene.grid.cols;

      // ISG table first: a table the controller would refuse stops the command before any file is written.
      std::optional<compensation::IsgTable> isg;
      compensation::IsgOptions isg_options;
      isg_options.limits.max_records = opt->isg_max_records;
      if (opt->isg_table) {
        isg = compensation::make_isg_table(wb.machine, isg_options);
        compensation::check_isg_table(*isg, isg_options.limits);
      }

      compensation::CompensationOptions co;
      co.method = opt->method == "paper"   ? compensation::Method::Paper
                  : opt->method == "cycle" ? compensation::Method::Cycle
                                           : compensation::Method::Flank;
      co.step_mm = opt->step;
      const auto before = grinding::simulate_topology(wb.setup, wb.process(), so);
      const auto table = compensation::compute_corrections(wb.setup, wb.process(), {wb.machine, wb.scene.machine.datum_face_z_mm}, co);
      const compensation::CompensatedProcess corrected(wb.process(), table);
      const auto after = grinding::simulate_topology(wb.setup, corrected, so);
      // What a grinding cycle can take (docs/compensation.md): index and lead corrections per space, Y and A fixed.
      // The gear is ground again with exactly that, so the after-state of the cycle form is shown, not assumed.
      const auto cycle = compensation::make_cycle_corrections(table, g.twist_rad_per_mm(), opt->lead_step);
      std::vector<compensation::CorrectionRow> cycle_rows = table.rows();
      for (auto& r : cycle_rows) r.correction = cycle.at(r.space, r.machine_axes.z);
      const compensation::CorrectionTable cycle_table(std::move(cycle_rows));
      const compensation::CompensatedProcess cycle_corrected(wb.process(), cycle_table);
      const double max_cycle = grinding::largest_abs_deviation_um(grinding::simulate_topology(wb.setup, cycle_corrected, so));

      // The after-state as a distribution (docs/monte-carlo.md), before any file is written: a prediction refused by
      // its work estimate (--max-time-s) leaves the output folder as it was.
      // Under MPI (geartopo-mpi) every rank computes its shard here and rank 0 gathers them; the other ranks leave.
      std::optional<pipeline::MonteCarloRun> mc_run;
      if (mc.samples > 0) {
        const MonteCarloDriver& driver = monte_carlo_driver();
        pipeline::MonteCarloOptions watched = driver.this_process(mc);
        MonteCarloWatch watch(driver.samples_on_this_process(watched), watched.threads, opt->mc.max_time_s,
                              driver.split_hint(), mc.adaptive_tolerance_um > 0.0);
        watched.on_sample_done = watch.callback();
        watched.on_prepared = [&watch] { watch.prepared(); };
        mc_run = driver.run(wb, table, watched);
        if (!mc_run) return 0; // an MPI rank other than 0: its samples are on rank 0, which writes the files
        // What `merge` checks that every shard shares: the scene, its tables and the settings behind the corrections.
        mc_run->scene_fingerprint =
            pipeline::scene_fingerprint(wb, fmt::format("method={} step_mm={}", opt->method, opt->step));
        mc_run->gear = pipeline::gear_record(g.spec()); // also when rank 0 gathered the samples as numbers (MPI)
      }

      table.write_csv(out / "corrections.csv");
      cycle.write_csv(out / "cycle_corrections.csv");
      grinding::write_topology_csv(out / "topology_before.csv", before);
      grinding::write_topology_csv(out / "topology_after.csv", after);
      grinding::write_traces_csv(out / "traces_before.csv", before);
      grinding::write_traces_csv(out / "traces_after.csv", after);

      const workbench::IsoResult iso_b = workbench::evaluate_iso(g, wb.setup.ranges(), before, opt->iso), iso_a = workbench::evaluate_iso(g, wb.setup.ranges(), after, opt->iso);
      const double max_b = grinding::largest_abs_deviation_um(before), max_a = grinding::largest_abs_deviation_um(after);
      nlohmann::json j;
      j["scene"] = wb.scene.name;
      j["units"] = "µm; plus material positive; profile/helix values in the direction each section names (iso_direction)";
      j["before"] = report::iso_json(iso_b);
      // The nominal after-state is the model corrected by itself (≈ 0 by construction): kept under a name that says
      // so, never `after`; what the machine would grind is `prediction`, and `improvement` comes from it alone.
      j["nominal_after"] = report::iso_json(iso_a);
      j["nominal_after_meaning"] = report::kNominalAfterMeaning;
      j["largest_abs_deviation_um"] = {{"before", max_b}, {"nominal_after", max_a}};
      const auto cmax = table.max_abs();
      j["compensation"] = {{"method", opt->method},
                           {"rows", table.rows().size()},
                           {"rows_outside_strokes", table.rows_outside_strokes()},
                           {"max_correction", {{"dX_um", units::um_from_mm(cmax(0))}, {"dY_um", units::um_from_mm(cmax(1))}, {"dZ_um", units::um_from_mm(cmax(2))},
                                               {"dA_urad", units::urad_from_rad(cmax(3))}, {"dC_urad", units::urad_from_rad(cmax(4))}}}};
      const auto& qb = iso_b.evaluation.classification.quantities;
      const auto& qa = iso_a.evaluation.classification.quantities;
      j["cycle"] = {{"file", "cycle_corrections.csv"},
                    {"lead_step_mm", opt->lead_step},
                    {"setup_dY_um", units::um_from_mm(cycle.setup_dY_mm)},
                    {"setup_dA_urad", units::urad_from_rad(cycle.setup_dA_rad)},
                    {"not_carried_Y_um", units::um_from_mm(cycle.y_not_carried_mm)},
                    {"not_carried_A_urad", units::urad_from_rad(cycle.a_not_carried_rad)},
                    {"nominal_largest_abs_deviation_after_um", max_cycle}};
      std::string isg_summary;
      if (isg) {
        // What the position-only table leaves: the machine's geometric errors with the wheel centre put back.
        compensation::write_isg_table(out / "isg_compensation.csv", *isg, isg_options.limits);
        const compensation::PositionCompensatedProcess position_only(wb.machine_process, Eigen::Vector3d::Zero());
        const workbench::WithDesignMotion designed(wb, position_only); // the drawing's helix motions still run
        const auto left = grinding::simulate_topology(wb.setup, designed.process(), so);
        const auto iso_left = workbench::evaluate_iso(g, wb.setup.ranges(), left, opt->iso);
        const double max_left = grinding::largest_abs_deviation_um(left);
        nlohmann::json left_json = {{"largest_abs_deviation_um", max_left}};
        isg_summary = fmt::format("left after the table: largest |dev| {:.2f} µm", max_left);
        for (const auto& q : iso_left.evaluation.classification.quantities) {
          left_json[std::string(evaluation::symbol(q.quantity))] = q.worst_value_um;
          isg_summary += fmt::format(", {} {:.2f} µm", evaluation::symbol(q.quantity), q.worst_value_um);
        }
        j["isg_table"] = {{"file", "isg_compensation.csv"},
                          {"records", isg->records()},
                          {"max_records", isg_options.limits.max_records},
                          {"tool_centre_point", "wheel centre"},
                          {"scope", "geometric machine errors only (the scene's effects are not in the table)"},
                          {"nominal_left_after_table", left_json}};
      }
      j["warnings"] = nlohmann::json::array();
      if (const std::string w = compensation_made_worse(max_b, max_a); !w.empty()) {
        say("geartopo: warning: " + w);
        j["warnings"].push_back(w);
      }
      // The nominal `after` is the model compensating itself (≈ 0 by construction); the prediction grinds with a
      // machine drawn within the scene's uncertainties.
      std::optional<pipeline::MonteCarloSummary> prediction;
      if (mc_run) {
        pipeline::write_run_csv(out / "prediction_samples.csv", *mc_run);
        if (mc.shards == 1) {
          prediction = pipeline::summarise(*mc_run);
          write_prediction(out, *prediction);
          j["prediction"] = report::prediction_json(*prediction);
          j["improvement"] = report::improvement_json(*prediction);
          if (const std::string w = prediction_made_worse(*prediction); !w.empty()) {
            say("geartopo: warning: " + w);
            j["warnings"].push_back(w);
          }
        }
      }
      output::write_text_atomically(out / "iso1328.json", j.dump(2) + "\n");

      const auto [lb, hb] = range_of(before);
      const auto [la, ha] = range_of(after);
      std::cout << fmt::format("Compensation ({} method), {} path samples every {} mm, {} outside the strokes\n", opt->method,
                               table.rows().size(), opt->step, table.rows_outside_strokes());
      std::cout << fmt::format("  largest corrections: X {:.2f} µm, Y {:.2f} µm, Z {:.2f} µm, A {:.2f} µrad, C {:.2f} µrad\n",
                               units::um_from_mm(cmax(0)), units::um_from_mm(cmax(1)), units::um_from_mm(cmax(2)), units::urad_from_rad(cmax(3)), units::urad_from_rad(cmax(4)));
      std::cout << fmt::format("  topology (all teeth, {}×{} grid): before {:.2f} … {:.2f} µm; {}: {:.2f} … {:.2f} µm\n", so.rows,
                               so.cols, lb, hb, report::kNominalLabel, la, ha);
      if (!prediction)
        std::cout << fmt::format("  largest |deviation|: {:.2f} µm before; {}: {:.2f} µm (no prediction: --samples 0 or "
                                 "a shard, so no improvement figure)\n", max_b, report::kNominalLabel, max_a);
      std::cout << fmt::format("  with the cycle table (index + lead per space, Y {:+.2f} µm and A {:+.2f} µrad per gear; "
                               "not carried: Y {:.2f} µm, A {:.2f} µrad): largest |deviation| {:.2f} µm, {}\n",
                               units::um_from_mm(cycle.setup_dY_mm), units::urad_from_rad(cycle.setup_dA_rad),
                               units::um_from_mm(cycle.y_not_carried_mm), units::urad_from_rad(cycle.a_not_carried_rad),
                               max_cycle, report::kNominalLabel);
      if (prediction) {
        for (const auto& l : report::prediction_lines(*prediction)) std::cout << "  " << l << "\n";
        for (const auto& l : report::improvement_lines(*prediction)) std::cout << "  " << l << "\n";
      }
      // Without a prediction the nominal after-state is shown as what it is (the model compensating itself), with no
      // "% better": that would be a tautology.
      if (!prediction)
        std::cout << fmt::format("  {:<6} {:>10} {:>10}  {:>6} {:>6}   (nominal: the model corrected by itself, ≈ 0 by "
                                 "construction; not a result)\n", "ISO", "before", "nominal", "class", "");
      for (size_t i = 0; !prediction && i < qb.size() && i < qa.size(); ++i)
        std::cout << fmt::format("  {:<6} {:>10.2f} {:>10.2f}  {:>6} → {}\n", evaluation::symbol(qb[i].quantity),
                                 qb[i].worst_value_um, qa[i].worst_value_um,
                                 evaluation::class_label(qb[i].flank_class),
                                 evaluation::class_label(qa[i].flank_class));
      const auto& cb = iso_b.evaluation.classification;
      const auto& ca = iso_a.evaluation.classification;
      if (!prediction && cb.overall && ca.overall)
        std::cout << fmt::format("  overall flank tolerance class: {} before; {}: {}\n", evaluation::class_label(*cb.overall),
                                 report::kNominalLabel, evaluation::class_label(*ca.overall));
      if (isg)
        std::cout << fmt::format("  ISG volumetric table (isg_compensation.csv, {} records; corrects the wheel position, "
                                 "not its orientation): {}\n",
                                 isg->records(), isg_summary);
      std::cout << "wrote " << out.string() << "/corrections.csv, cycle_corrections.csv, topology_before.csv, topology_after.csv, "
                   "iso1328.json" << (isg ? ", isg_compensation.csv" : "") << (mc.samples > 0 ? ", prediction_samples.csv" : "")
                << (prediction ? ", prediction.json, prediction.txt" : "") << "\n";
      finish_output_folder(*folder);
      json.emit(j);
      return 0;
    };
  });
}

} // namespace geartopo::app
