// Shared set-up of the benchmarks: the default and truth scenes and everything built from them (scene::Workbench),
// loaded once per benchmark binary.
#pragma once

#include "scene/workbench.hpp"

#include <string>

namespace geartopo::bench {

inline const std::string kDefaultScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";
inline const std::string kTruthScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml";

inline const scene::Workbench& default_scene() {
  static const scene::Workbench b(kDefaultScene);
  return b;
}

inline const scene::Workbench& truth_scene() {
  static const scene::Workbench b(kTruthScene);
  return b;
}

} // namespace geartopo::bench
