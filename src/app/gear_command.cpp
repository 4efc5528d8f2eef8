#include "app/gear_command.hpp"

#include "app/commands.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_gear_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<GearOptions>();
  CLI::App* cmd = app.add_subcommand("gear", "Gear geometry (ISO 21771) of a scene's gear; optionally its mesh");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML; units named in its keys)")->required();
  cmd->add_flag("--json", opt->json, "Print one JSON object (lengths mm, angles deg) instead of a table");
  cmd->add_option("--mesh", opt->mesh, "Write all teeth, flanks, tip, root and end faces as a triangle mesh "
                                       "(.ply, .obj, .stl or .off; mm)")
      ->check(non_empty_path());
  cmd->callback([&action, opt] { action = [opt] { return run_gear(*opt); }; });
}

} // namespace geartopo::app
