// geartopo — the measuring machine's own pitch table (a Klingelnberg export's f_p, F_p per tooth and flank) beside
// geartopo's ISO 1328-1 evaluation of the same traces, with the differences; a difference above 0.1 µm is flagged and
// its likely cause named (docs/measurement-formats.md, "The machine's pitch table"). Units: µm.
#pragma once

#include "geartopo/evaluation/gear_evaluation.hpp"
#include "geartopo/measurement/klingelnberg.hpp"

#include <string>
#include <vector>

namespace geartopo::workbench {

inline constexpr double kMachineMismatchUm = 0.1; ///< a difference above this is flagged

struct MachinePitchRow {
  int tooth = 1;
  Flank side = Flank::Left;
  double machine_fp_um = 0.0, machine_Fp_um = 0.0;   ///< the table's
  double geartopo_fp_um = 0.0, geartopo_Fp_um = 0.0; ///< f_p,j = e_{j+1} − e_j, F_p,j = e_j − e_1 (evaluation/pitch.hpp)
  bool flagged = false;                              ///< |difference| of f_p or F_p above kMachineMismatchUm
};

struct MachinePitchComparison {
  std::vector<MachinePitchRow> rows;     ///< the table's rows whose side geartopo evaluated
  double max_abs_fp_difference_um = 0.0, max_abs_Fp_difference_um = 0.0;
  std::size_t flagged = 0;
  std::string likely_cause; ///< when any is flagged: which other convention would make the table agree, else "filter,
                            ///< measuring diameter or evaluation range"
};

/// The table's rows beside the evaluation's pitch of the same side (only sides with all z flanks evaluated).
MachinePitchComparison compare_machine_pitch(const std::vector<measurement::KlingelnbergPitchRow>& table,
                                             const evaluation::GearEvaluation& evaluation);

} // namespace geartopo::workbench
