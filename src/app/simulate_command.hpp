// geartopo simulate SCENE --out DIR [--method exact|linear] [--teeth 1,18|all] [--dense NxM] [--max-time-s S]: the
// flanks as ground, with the scene's machine errors and effects: topology and traces (µm), flank meshes (mm).
#pragma once

#include "app/work_estimates.hpp"

#include <string>

namespace geartopo::app {

struct SimulateOptions {
  std::string scene, out, method = "exact", teeth, dense;
  double max_time_s = kMaxJobSeconds;
  bool teeth_given = false; ///< --teeth on the command line (given but empty is refused, not "not given")
};

/// The command's work once its flags are parsed (simulate_command.cpp); returns the exit code.
int run_simulate(const SimulateOptions& opt);

} // namespace geartopo::app
