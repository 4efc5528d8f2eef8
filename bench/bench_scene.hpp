// Shared set-up of the benchmarks: the default and truth scenes and everything built from them (workbench::Workbench),
// loaded once per benchmark binary.
#pragma once

#include "geartopo/workbench/workbench.hpp"

#include <string>

namespace geartopo::bench {

inline const std::string kDefaultScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";
inline const std::string kTruthScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml";

inline const workbench::Workbench& default_scene() {
  static const workbench::Workbench b(kDefaultScene);
  return b;
}

inline const workbench::Workbench& truth_scene() {
  static const workbench::Workbench b(kTruthScene);
  return b;
}

} // namespace geartopo::bench
