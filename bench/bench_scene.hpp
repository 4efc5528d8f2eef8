// Shared set-up of the benchmarks: the default and truth scenes and everything built from them (workbench::Workbench),
// loaded once per benchmark binary.
#pragma once

#include "geartopo/workbench/workbench.hpp"

#include <string>

namespace geartopo::bench {

inline const std::string kDefaultScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";
inline const std::string kTruthScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml";
inline const std::string kCrownedScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35-crowned.yaml";

inline const workbench::Workbench& default_scene() {
  static const workbench::Workbench b(kDefaultScene);
  return b;
}

inline const workbench::Workbench& truth_scene() {
  static const workbench::Workbench b(kTruthScene);
  return b;
}

/// The default gear as drawn: C_α, tip relief, C_β ground twist-free (docs/modifications.md).
inline const workbench::Workbench& crowned_scene() {
  static const workbench::Workbench b(kCrownedScene);
  return b;
}

} // namespace geartopo::bench
