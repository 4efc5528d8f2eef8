// geartopo series SERIES --out DIR [--aqdef FILE.dfq]: a production series — per gear its ISO 1328-1 values and
// residual against the model, the across-series laws (thermal drift, wheel wear and re-dress, correction steps) with
// σ, the next gear predicted, when the drawing's class is expected to be lost, run charts, and the AQDEF export.
#pragma once

#include "app/commands.hpp"

#include "geartopo/series/aqdef_export.hpp"

#include <string>

namespace geartopo::app {

struct SeriesOptions {
  std::string series, out, aqdef;
};

/// The command's work once its flags are parsed (series_command.cpp); returns the exit code.
int run_series(const SeriesOptions& opt);

/// `geartopo report SERIES --out DIR`: the series' files and its report page (index.html, docs/series.md).
int run_series_report(const std::string& series_file, const std::string& out_dir);

/// An AQDEF file's header for this scene (docs/aqdef.md): part number its drawing (else its part, else its name),
/// description its part (else its name), machine `machine` (else the scene's machine), every value's batch `batch`.
series::AqdefHeader aqdef_header(const Workbench& wb, const std::string& batch, const std::string& machine);

} // namespace geartopo::app
