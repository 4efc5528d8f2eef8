// geartopo evaluate SCENE --out DIR [--method exact|linear] [--traces FILE [--machine-values FILE]]
// [--prediction FILE [--prediction-side before|after] [--before-traces FILE]]: ISO 1328-1:2013 deviations and classes of the simulated gear
// or of measured traces, beside a measuring machine's own values or a prediction.
#pragma once

#include "app/measurement_options.hpp"

#include "geartopo/workbench/iso_evaluation.hpp"

#include <string>

namespace geartopo::app {

struct EvaluateOptions {
  std::string scene, out, method = "exact", traces, machine_values, prediction, side = "after", aqdef;
  std::string before_traces; ///< gear 1's traces (ground without the corrections), checked against the before band
  workbench::IsoOptions iso;
  KlingelnbergFlags mka;
  bool iso_direction_given = false, helix_slope_sign_given = false; ///< the ISO flags on the command line
};

/// The command's work once its flags are parsed (evaluate_command.cpp); returns the exit code.
int run_evaluate(const EvaluateOptions& opt);

} // namespace geartopo::app
