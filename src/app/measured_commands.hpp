// geartopo compare / diagnose / plan SCENE --measured F: measured − model, which effect is missing, what to measure
// next. Each command's flags, and its work once they are parsed (run_compare.cpp, run_diagnose.cpp, run_plan.cpp),
// which makes the library call both front ends make (commands/measured.hpp) and prints and writes its results.
#pragma once

#include "app/measurement_options.hpp"

#include <string>
#include <vector>

namespace geartopo::app {

/// The flags every command on a measurement takes.
struct MeasuredFlags {
  std::string scene, measured, out;
  double noise = 0.0; ///< µm; 0: estimated
  KlingelnbergFlags mka;
};

struct CompareFlags : MeasuredFlags {
  bool json = false;
};
int run_compare(const CompareFlags& opt);

struct DiagnoseFlags : MeasuredFlags {
  bool json = false, scene_uncertainty = false;
  std::vector<std::string> candidates;
};
int run_diagnose(const DiagnoseFlags& opt);

struct PlanFlags : MeasuredFlags {
  std::string layout = "grid";
};
int run_plan(const PlanFlags& opt);

} // namespace geartopo::app
