// geartopo run SCENE --out DIR: the main job — simulate, evaluate (ISO 1328-1), compensate, compare and diagnose when
// there is a measurement, and write the report — with a short summary.
#pragma once

#include "app/measurement_options.hpp"
#include "app/monte_carlo_flags.hpp"

#include "geartopo/workbench/iso_evaluation.hpp"

#include <string>

namespace geartopo::app {

struct RunOptions {
  std::string scene, out, measured, teeth, method = "flank", simulation = "exact";
  double step = 2.0, noise = 0.0; ///< mm; µm (0: estimated)
  KlingelnbergFlags mka;
  workbench::IsoOptions iso;
  MonteCarloFlags mc;
  bool json = false;
  bool teeth_given = false; ///< --teeth on the command line: it stands in for the scene's measurement.teeth
};

/// The command's work once its flags are parsed (run_command.cpp); returns the exit code.
int run_main_job(const RunOptions& opt);

} // namespace geartopo::app
