// geartopo — what the commands on a measurement share once their flags are parsed: the scene and the measurement as
// the commands library takes them (commands/measured.hpp).
#pragma once

#include "app/measured_commands.hpp"

#include "geartopo/commands/measured.hpp"

#include <filesystem>
#include <memory>
#include <string>

namespace geartopo::app {

/// The scene file read, built and checked, with its text (for the completed scene) and folder.
struct LoadedScene {
  std::string file;                       ///< as given on the command line (files and messages say it so)
  std::unique_ptr<workbench::Workbench> wb;
  std::string text;
  commands::SceneInput input() const { return {*wb, file, text, std::filesystem::path(file).parent_path()}; }
};
LoadedScene load_scene_for(const MeasuredFlags& opt);

/// How the CLI names the arguments the commands library checks: by their flags.
commands::ArgumentNames cli_argument_names();

} // namespace geartopo::app
