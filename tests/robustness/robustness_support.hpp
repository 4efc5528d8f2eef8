// Shared helpers of the robustness suite: where the corpus is, the default scene built once, running the CLI.
#pragma once

#include "geartopo/workbench/workbench.hpp"

#include <filesystem>
#include <string>

#include <unistd.h>

namespace geartopo::robustness {

inline const std::filesystem::path kSourceDir = GEARTOPO_SOURCE_DIR;
inline const std::filesystem::path kCorpus = kSourceDir / "tests/robustness/corpus";
inline const std::filesystem::path kDefaultScene = kSourceDir / "scenes/skmc1200w-mn14-z35.yaml";

/// The default scene and what is built from it, once per test binary.
inline const workbench::Workbench& default_scene() {
  static const workbench::Workbench d(kDefaultScene);
  return d;
}

/// A temporary path unique to this process (ctest runs tests in parallel processes).
inline std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("geartopo_robustness_" + std::to_string(::getpid()) + "_" + name);
}

} // namespace geartopo::robustness
