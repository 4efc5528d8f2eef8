// geartopo — the measuring machine's own profile and helix values (a Klingelnberg value file's f_Hα, f_fα, F_α, f_Hβ,
// f_fβ, F_β per tooth and flank) beside geartopo's ISO 1328-1 evaluation of the same traces (the export's curves), with
// the differences; a difference above 0.1 µm is flagged and its likely cause found by evaluating the alternatives
// (docs/measurement-formats.md, "The machine's values beside geartopo's"). Units: µm, mm.
#pragma once

#include "geartopo/evaluation/gear_evaluation.hpp"
#include "geartopo/gears/evaluation_ranges.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/measurement/klingelnberg_values.hpp"
#include "geartopo/workbench/machine_pitch.hpp"

#include <string>
#include <vector>

namespace geartopo::workbench {

struct MachineFlankRow {
  int tooth = 1;
  Flank side = Flank::Left;
  measurement::MachineQuantity quantity = measurement::MachineQuantity::ProfileSlope;
  double machine_um = 0.0;  ///< the value file's
  double geartopo_um = 0.0; ///< geartopo's evaluation of the trace (GearEvaluation::flanks, its conventions)
  double trace_position_mm = 0.0; ///< the trace evaluated: a profile's axial position z, a helix trace's diameter d
  bool flagged = false;           ///< |machine − geartopo| > kMachineMismatchUm
  int line = 0;                   ///< of the machine value
};

/// Which other reading makes every value of a quantity agree (each tested numerically on all its rows).
enum class MachineCause {
  None,            ///< nothing flagged
  OppositeSign,    ///< the machine's slope has the other sign (f_Hα, f_Hβ)
  Direction,       ///< the machine reports along the other direction: factor cos β_b (or 1/cos β_b)
  FaceWidth,       ///< f_Hβ referred to the face width b instead of L_β: factor b / L_β
  EvaluationRange, ///< the export's own evaluation range (header d1 … d2, b1 … b2)
  MeasuringRange,  ///< the whole measured trace
  Filter,          ///< slope agrees, form and total both smaller on every flagged flank: consistent with a filter
                   ///< (not evaluated: the machine's filter is not known)
  Unexplained,     ///< none of the above
};

struct MachineQuantitySummary {
  measurement::MachineQuantity quantity = measurement::MachineQuantity::ProfileSlope;
  std::size_t rows = 0, flagged = 0;
  double max_abs_difference_um = 0.0;
  MachineCause cause = MachineCause::None;
  std::string likely_cause; ///< the cause in words, with the numbers and the export's setting that support it
};

struct MachineFlankComparison {
  std::vector<MachineFlankRow> rows;              ///< per tooth, flank and quantity, in the file's tooth order
  std::vector<MachineQuantitySummary> quantities; ///< the six quantities, those with rows
  std::size_t flagged = 0;
  std::vector<std::string> not_compared; ///< machine values without a geartopo value or with a placeholder
};

/// The value file's per-tooth values (first position) beside `evaluation`'s flanks of the same `traces` (the flanks
/// geartopo evaluated, over `ranges`). `curves`: the export whose traces these are, for its evaluation range (d1 … d2,
/// b1 … b2) as an alternative reading; nullptr: that reading is not tried.
MachineFlankComparison compare_machine_flank_values(const measurement::KlingelnbergValues& machine,
                                                    const gears::GearGeometry& g, const gears::EvaluationRanges& ranges,
                                                    const std::vector<grinding::FlankTopology>& traces,
                                                    const evaluation::GearEvaluation& evaluation,
                                                    const measurement::KlingelnbergFile* curves = nullptr);

/// "opposite-sign", "direction", … for JSON; "" for None.
const char* to_string(MachineCause c);

} // namespace geartopo::workbench
