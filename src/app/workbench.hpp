// geartopo — everything a command needs, built once from one scene: the scene, the grinding set-up (gear, wheel,
// path), the machine model and the grinding process it drives. Not copyable: the process refers to the machine.
#pragma once

#include "grinding/grinding_setup.hpp"
#include "grinding/machine_process.hpp"
#include "machine/machine_model.hpp"
#include "scene/scene.hpp"

#include <string>
#include <vector>

namespace geartopo::app {

struct Workbench {
  explicit Workbench(const std::string& scene_file);
  Workbench(const Workbench&) = delete;
  Workbench& operator=(const Workbench&) = delete;

  scene::Scene scene;
  grinding::GrindingSetup setup;
  machine::MachineModel machine;
  grinding::MachineProcess process;
};

/// "all" → {} (every tooth); "1,18" → {1, 18}. Throws CLI::ValidationError naming the option.
std::vector<int> parse_teeth(const std::string& text, int teeth);
/// "50x100" → (50, 100). Throws CLI::ValidationError.
std::pair<int, int> parse_grid_size(const std::string& text);

} // namespace geartopo::app
