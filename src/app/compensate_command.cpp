#include "app/compensate_command.hpp"

#include "app/commands.hpp"
#include "app/parsers.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_compensate_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<CompensateOptions>();
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
      ->check(finite_in(limits::kMinStepMm, limits::kMaxStepMm));
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
  cmd->callback([&action, opt] { action = [opt] { return run_compensate(*opt); }; });
}

} // namespace geartopo::app
