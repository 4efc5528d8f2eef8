// Shared helpers of the robustness suite: where the corpus is, the default scene built once, running the CLI.
#pragma once

#include "grinding/grinding_setup.hpp"
#include "grinding/machine_process.hpp"
#include "machine/machine_model.hpp"
#include "scene/scene.hpp"

#include <filesystem>
#include <string>

#include <unistd.h>

namespace geartopo::robustness {

inline const std::filesystem::path kSourceDir = GEARTOPO_SOURCE_DIR;
inline const std::filesystem::path kCorpus = kSourceDir / "tests/robustness/corpus";
inline const std::filesystem::path kDefaultScene = kSourceDir / "scenes/skmc1200w-mn14-z35.yaml";

/// The default scene and what is built from it (as tests/diagnosis/test_diagnosis.cpp builds it; no effects).
struct DefaultScene {
  DefaultScene()
      : sc(scene::load_scene(kDefaultScene)), setup(sc.gear, sc.wheel, sc.process), model(sc.machine.model()),
        machine(model, sc.machine.datum_face_z_mm) {}
  scene::Scene sc;
  grinding::GrindingSetup setup;
  machine::MachineModel model;
  grinding::MachineProcess machine;
};

inline const DefaultScene& default_scene() {
  static const DefaultScene d;
  return d;
}

/// A temporary path unique to this process (ctest runs tests in parallel processes).
inline std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("geartopo_robustness_" + std::to_string(::getpid()) + "_" + name);
}

} // namespace geartopo::robustness
