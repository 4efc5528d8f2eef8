// geartopo compensate SCENE --out DIR [--method paper|flank|cycle] [--step MM] [--lead-step MM] [--isg-table]
// [Monte Carlo flags]: axis corrections along the wheel path, the gear before and after (nominal and predicted),
// the cycle table and optionally the ISG/TF5280 volumetric table.
#pragma once

#include "app/monte_carlo_flags.hpp"

#include "geartopo/workbench/iso_evaluation.hpp"

#include <string>

namespace geartopo::app {

struct CompensateOptions {
  std::string scene, out, method = "flank";
  double step = 2.0;           ///< mm along each stroke
  double lead_step = 5.0;      ///< mm, the cycle table's largest Z step
  bool isg_table = false;      ///< issue 15: the machine's errors as an ISG/TF5280 volumetric table
  int isg_max_records = 2000;
  workbench::IsoOptions iso;
  MonteCarloFlags mc;
  bool json = false;
};

/// The command's work once its flags are parsed (compensate_command.cpp); returns the exit code. Under MPI
/// (geartopo-mpi) every rank runs it; the ranks other than 0 return once their samples are gathered.
int run_compensate(const CompensateOptions& opt);

} // namespace geartopo::app
