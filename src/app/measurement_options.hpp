// geartopo — the options of a command that reads a measurement: --measured FILE and the Klingelnberg reader's
// --mka-… flags (docs/measurement-formats.md).
#pragma once

#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace geartopo::app {

/// The Klingelnberg reader's options as a command line set them, and which --mka-… flags it gave (in order): a flag
/// given for a file that is not an export is refused (refuse_mka_flags_without_export).
struct KlingelnbergFlags {
  measurement::KlingelnbergOptions options;
  std::vector<std::string> given;
  /// --measured-against design|involute (add_measurement_options): what a file without design_um is measured from,
  /// for every format; as_file when not given.
  measurement::MeasuredAgainst against = measurement::MeasuredAgainst::as_file;
};

/// The Klingelnberg reader's options as flags of a command that reads measurements (docs/measurement-formats.md):
/// --mka-spacing roll-length|diameter, --mka-direction transverse|normal, --mka-signs raw|din.
void add_klingelnberg_options(CLI::App* cmd, KlingelnbergFlags& flags);

/// `--measured FILE` (every format the readers tell apart by content, docs/measurement-formats.md),
/// `--measured-against design|involute` and the Klingelnberg options: one text for compare, diagnose and plan
/// (required) and run and report (optional: the scene's measurement.measured when not given).
void add_measurement_options(CLI::App* cmd, std::string& file, KlingelnbergFlags& flags, bool required = true);

/// `--measured-against design|involute` alone, for a command that reads measured traces (evaluate --traces).
void add_measured_against_option(CLI::App* cmd, KlingelnbergFlags& flags);

/// Throws CLI::ValidationError naming the first --mka-… flag given when `file` is not a Klingelnberg export
/// (measurement::looks_like_klingelnberg): the flag would do nothing. Before the file is read; also when `file` is
/// empty (nothing is read).
void refuse_mka_flags_without_export(const std::string& file, const KlingelnbergFlags& flags);

/// What `file` is measured from: the flag, else the scene's measurement.measured_against when `file` is the scene's
/// measurement, else as the file says.
measurement::MeasuredAgainst measured_against(const workbench::Workbench& wb, const std::string& file,
                                              const KlingelnbergFlags& flags);

/// The measured points of `file` on the workbench's gear (measurement::read_any_measurement); the reader's warnings
/// (blocks of an export it did not use, …) on stderr. Throws InputError; refuse_mka_flags_without_export first.
std::vector<measurement::MeasuredPoint> read_measured_points(const workbench::Workbench& wb, const std::string& file,
                                                             const KlingelnbergFlags& flags,
                                                             measurement::ReadCounts* counts = nullptr);

} // namespace geartopo::app
