// geartopo report SCENE [--measured FILE] --out DIR: the figures (PNG, rendered off-screen) and an offline
// index.html of the whole job, with the data files beside them.
#pragma once

#include "app/measurement_options.hpp"
#include "app/monte_carlo_flags.hpp"

#include "geartopo/workbench/iso_evaluation.hpp"

#include <string>
#include <vector>

namespace geartopo::app {

struct ReportOptions {
  std::string scene, measured, out;
  KlingelnbergFlags mka;
  workbench::IsoOptions iso;
  MonteCarloFlags mc;
  /// The flags given besides SCENE and --out, in order: a series file takes none (its gears name their measurements,
  /// its spec the rest), so each is refused rather than ignored.
  std::vector<std::string> other_flags_given;
};

/// The command's work once its flags are parsed (report_command.cpp); returns the exit code.
int run_report(const ReportOptions& opt);

} // namespace geartopo::app
