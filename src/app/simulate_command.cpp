#include "app/simulate_command.hpp"

#include "app/commands.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <memory>

namespace geartopo::app {

void register_simulate_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate line-contact profile grinding with the scene's machine "
                                                 "errors; write topology (µm), traces and flank meshes (mm)");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML)")->required();
  cmd->add_option("--out", opt->out, "Output directory (created)")->required()->check(non_empty_path());
  cmd->add_option("--method", opt->method, "exact (envelope of the actual wheel poses) or linear (first order)")
      ->check(CLI::IsMember({"exact", "linear"}));
  CLI::Option* teeth = cmd->add_option("--teeth", opt->teeth, "Teeth to simulate: all (default, or the scene's list) or e.g. 1,18");
  cmd->add_option("--dense", opt->dense, "Also a dense grid per flank, ROWSxCOLS (e.g. 50x100) → dense.csv");
  cmd->add_option("--max-time-s", opt->max_time_s,
                  fmt::format("Refuse a simulation whose estimate (after its first flank) exceeds this wall time, s "
                              "(default {:g}: one day)",
                              opt->max_time_s))
      ->check(finite_in(1e-3, 1e9));
  cmd->callback([&action, opt, teeth] {
    opt->teeth_given = teeth->count() > 0;
    action = [opt] { return run_simulate(*opt); };
  });
}

} // namespace geartopo::app
