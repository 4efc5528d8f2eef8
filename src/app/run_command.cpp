#include "app/run_command.hpp"

#include "app/commands.hpp"
#include "app/parsers.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_run_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "The main job: simulate, evaluate (ISO 1328-1), compensate, compare and diagnose "
                                            "when there is a measurement, and write the report");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML)")->required();
  cmd->add_option("--out", opt->out, "Output directory (created; what an earlier run wrote there and this one does not is removed)")
      ->required()
      ->check(non_empty_path());
  add_measurement_options(cmd, opt->measured, opt->mka, false);
  cmd->add_option("--teeth", opt->teeth, "Teeth to simulate: all (default, or the scene's list) or e.g. 1,18");
  cmd->add_option("--method", opt->method, "Compensation: paper, flank (default) or cycle (as `geartopo compensate`)")
      ->check(CLI::IsMember({"paper", "flank", "cycle"}));
  cmd->add_option("--simulation", opt->simulation, "Simulation of the topology: exact (default) or linear (first order)")
      ->check(CLI::IsMember({"exact", "linear"}));
  cmd->add_option("--step", opt->step, "Correction table spacing along each stroke, mm (default 2)")->check(finite_in(limits::kMinStepMm, limits::kMaxStepMm));
  cmd->add_option("--noise-um", opt->noise, "Probe noise σ of the measurement, µm (default: estimated from the residual)")
      ->check(probe_sigma_um());
  add_iso_options(cmd, opt->iso);
  add_monte_carlo_options(cmd, opt->mc, false);
  cmd->add_flag("--json", opt->json,
                "Print one JSON object on stdout instead of the text summary: iso1328.json's content, the report's path "
                "and, with a measurement, the comparison's RMS, the verdict and the chosen effect");
  CLI::Option* teeth = cmd->get_option("--teeth");
  cmd->callback([&action, opt, teeth] {
    opt->teeth_given = teeth->count() > 0;
    action = [opt] { return run_main_job(*opt); };
  });
}

} // namespace geartopo::app
