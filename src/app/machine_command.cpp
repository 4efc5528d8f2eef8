#include "app/machine_command.hpp"

#include "app/commands.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_machine_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<MachineOptions>();
  CLI::App* cmd = app.add_subcommand("machine", "Wheel pose of the scene's machine at one axis pose: ideal (Eq. 11), "
                                                "exact and first-order error twists, Jacobian J_M");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML)")->required();
  cmd->add_option("--pose", opt->pose, "Machine axes X_mm,Y_mm,Z_mm,A_deg,C_deg (machine coordinates)")
      ->required()
      ->expected(5)
      ->delimiter(',')
      ->check(finite_in(-1e5, 1e5)); // mm and deg: a machine's strokes are metres, its angles a few turns
  cmd->add_flag("--json", opt->json, "One JSON object: 4×4 poses (mm), twists (µm, µrad; workpiece frame), jacobian");
  cmd->callback([&action, opt] { action = [opt] { return run_machine(*opt); }; });
}

} // namespace geartopo::app
