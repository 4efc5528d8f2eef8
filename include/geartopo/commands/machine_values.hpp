// geartopo — measured traces evaluated, with what a measuring machine evaluated itself beside them, once for every
// front end (`geartopo evaluate --traces EXPORT [--machine-values VALUES]` and the Python module's machine_values):
// the traces read (a traces CSV or a Klingelnberg export), the machine's value file read when it is named (and a
// note when one lies beside the export unread: a stale one would be compared silently), and the export's pitch table
// and value file compared with geartopo's evaluation of the same traces. Units: µm.
#pragma once

#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/measurement/klingelnberg_values.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/workbench/machine_flank_values.hpp"
#include "geartopo/workbench/machine_pitch.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace geartopo::commands {

/// How a front end names the value-file argument: `--machine-values` / `values`, and how a user gives it a file
/// (`give` formats the file into e.g. `--machine-values F.mew` or `values="F.mew"`).
struct ValuesArgument {
  std::string name = "values";
  std::string give = "values=\"{}\"";
};

/// Measured traces, and what the measuring machine said about them.
struct TracesWithMachineValues {
  measurement::MeasuredTraces traces; ///< the flanks, whether an export, the reader's warnings, the export as read
  std::optional<measurement::KlingelnbergValues> machine_values; ///< the value file, when named
  std::vector<std::string> warnings; ///< the reader's and the value file's findings that are not errors
};

/// Reads `traces` (with the Klingelnberg reader's options `mka`; what a file without a design column is measured
/// from: `against`, measurement::read_any_traces) and, when `values_file` is not empty, the machine's value file,
/// which needs an export: otherwise ArgumentError naming `argument.name`. Throws InputError for a file that cannot be
/// read.
TracesWithMachineValues read_traces_with_machine_values(
    const workbench::Workbench& wb, const std::string& traces, const std::string& values_file,
    const measurement::KlingelnbergOptions& mka = {}, const ValuesArgument& argument = {},
    measurement::MeasuredAgainst against = measurement::MeasuredAgainst::as_file);

/// ISO 1328-1 evaluation of traces read from `file` (workbench::evaluate_iso): a trace the evaluation refuses (it
/// does not cover the evaluation range, too few points in it) is an InputError naming the file, and for an export
/// the line of the trace's head and its tooth, flank and kind — not a bare "trace refused".
workbench::IsoResult evaluate_measured_traces(const workbench::Workbench& wb, const measurement::MeasuredTraces& traces,
                                              const std::string& file, const workbench::IsoOptions& iso);

/// The machine's evaluation beside geartopo's `iso` of the same traces.
struct MachineValuesResult {
  std::optional<workbench::MachinePitchComparison> pitch;        ///< when the export has a pitch table
  std::optional<workbench::MachineFlankComparison> flank_values; ///< when a value file was read
  nlohmann::json json; ///< iso1328.json's "machine_pitch_table" and "machine_flank_values" (absent when none)
};
MachineValuesResult machine_values(const workbench::Workbench& wb, const TracesWithMachineValues& read,
                                   const workbench::IsoResult& iso);

} // namespace geartopo::commands
