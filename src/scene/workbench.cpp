#include "scene/workbench.hpp"

#include "effects/registry.hpp"

#include <utility>

namespace geartopo::scene {

Workbench::Workbench(Scene s)
    : scene(std::move(s)), setup(scene.gear, scene.wheel, scene.process), machine(scene.machine.model()),
      machine_process(machine, scene.machine.datum_face_z_mm), effects(make_effects(scene.effects, setup)) {
  if (!effects.empty()) effects_process = std::make_unique<effects::EffectsProcess>(machine_process, effects);
}

Workbench::Workbench(const std::filesystem::path& scene_file) : Workbench(load_scene(scene_file)) {}

std::vector<std::string> Workbench::effect_types() const {
  std::vector<std::string> out;
  for (const auto& e : scene.effects) out.push_back(e.type);
  return out;
}

std::vector<std::unique_ptr<effects::Effect>> make_effects(const std::vector<EffectSpec>& specs,
                                                           const grinding::GrindingSetup& setup) {
  std::vector<std::unique_ptr<effects::Effect>> out;
  for (const auto& s : specs) out.push_back(effects::make_effect(s.type, s.values, setup));
  return out;
}

} // namespace geartopo::scene
