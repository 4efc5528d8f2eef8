// geartopo — the measuring machine's own evaluation beside geartopo's, as iso1328.json holds it: the export's pitch
// table ("machine_pitch_table") and the value file's f_Hα … F_β ("machine_flank_values"); docs/measurement-formats.md,
// "The machine's values beside geartopo's". One builder each, for `geartopo evaluate` and the Python module.
// Units: µm, mm.
#pragma once

#include "geartopo/measurement/klingelnberg_values.hpp"
#include "geartopo/workbench/machine_flank_values.hpp"
#include "geartopo/workbench/machine_pitch.hpp"

#include <nlohmann/json.hpp>

namespace geartopo::report {

/// iso1328.json "machine_pitch_table": per row the table's and geartopo's f_p, F_p and whether it is flagged; the
/// largest differences, the number flagged, the threshold and the likely cause (null when nothing is flagged).
nlohmann::json machine_pitch_table_json(const workbench::MachinePitchComparison& c);

/// iso1328.json "machine_flank_values": the rows (machine, geartopo, difference = machine − geartopo, the trace's z or
/// d, the file's line), per quantity the largest |difference|, the number flagged and the cause, what was not
/// compared, and the value file's name, settings, filters and unread lines (`m`: the value file compared in `c`).
nlohmann::json machine_flank_values_json(const workbench::MachineFlankComparison& c,
                                         const measurement::KlingelnbergValues& m);

} // namespace geartopo::report
