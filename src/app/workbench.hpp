// geartopo — everything a command needs, built once from one scene: the scene, the grinding set-up (gear, wheel,
// path), the machine model and the grinding process it drives. Not copyable: the process refers to the machine.
#pragma once

#include "effects/effect.hpp"
#include "effects/effects_process.hpp"
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
  grinding::MachineProcess machine_process; ///< geometric errors only
  std::vector<std::unique_ptr<effects::Effect>> effects; ///< the scene's effects, bound to setup
  std::unique_ptr<effects::EffectsProcess> effects_process;

  /// What the machine does: geometric errors plus the scene's effects.
  const grinding::GrindingProcess& process() const {
    return effects_process ? static_cast<const grinding::GrindingProcess&>(*effects_process) : machine_process;
  }
};

/// Instances of a scene's effects, bound to a set-up.
std::vector<std::unique_ptr<effects::Effect>> make_effects(const std::vector<scene::EffectSpec>& specs,
                                                           const grinding::GrindingSetup& setup);

/// "all" → {} (every tooth); "1,18" → {1, 18}. Throws CLI::ValidationError naming the option.
std::vector<int> parse_teeth(const std::string& text, int teeth);
/// "50x100" → (50, 100). Throws CLI::ValidationError.
std::pair<int, int> parse_grid_size(const std::string& text);

} // namespace geartopo::app
