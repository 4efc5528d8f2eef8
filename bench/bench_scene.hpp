// Shared set-up of the benchmarks: a scene and everything built from it, the way tests/diagnosis/test_diagnosis.cpp
// builds it (set-up, machine model, machine process, the scene's effects on top). Loaded once per benchmark binary.
#pragma once

#include "effects/effects_process.hpp"
#include "effects/registry.hpp"
#include "grinding/grinding_setup.hpp"
#include "grinding/machine_process.hpp"
#include "machine/machine_model.hpp"
#include "scene/scene.hpp"

#include <memory>
#include <string>
#include <vector>

namespace geartopo::bench {

inline const std::string kDefaultScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";
inline const std::string kTruthScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml";

struct Built {
  explicit Built(const scene::Scene& s)
      : sc(s), setup(sc.gear, sc.wheel, sc.process), model(sc.machine.model()), machine(model, sc.machine.datum_face_z_mm) {
    std::vector<const effects::Effect*> list;
    for (const auto& spec : sc.effects) {
      effs.push_back(effects::make_effect(spec.type));
      effs.back()->set_values(spec.values);
      effs.back()->bind(setup);
      list.push_back(effs.back().get());
      in_scene.push_back(spec.type);
    }
    if (!list.empty()) process = std::make_unique<effects::EffectsProcess>(machine, list);
  }
  /// What the machine does, as the app's Workbench picks it: geometric errors, plus the scene's effects if any.
  const grinding::GrindingProcess& actual() const {
    return process ? static_cast<const grinding::GrindingProcess&>(*process) : machine;
  }
  Built(const Built&) = delete;
  Built& operator=(const Built&) = delete;

  scene::Scene sc;
  grinding::GrindingSetup setup;
  machine::MachineModel model;
  grinding::MachineProcess machine;
  std::vector<std::unique_ptr<effects::Effect>> effs;
  std::unique_ptr<effects::EffectsProcess> process; ///< null when the scene has no effects
  std::vector<std::string> in_scene;
};

inline const Built& default_scene() {
  static const Built b(scene::load_scene(kDefaultScene));
  return b;
}

inline const Built& truth_scene() {
  static const Built b(scene::load_scene(kTruthScene));
  return b;
}

} // namespace geartopo::bench
