// geartopo — flags read into the libraries' options: tooth lists, grid sizes, the ISO 1328-1 reporting conventions.
#pragma once

#include "geartopo/workbench/iso_evaluation.hpp"

#include <string>
#include <utility>
#include <vector>

namespace CLI {
class App;
}

namespace geartopo::app {

/// "all" → {} (every tooth); "1,18" → {1, 18}. Throws CLI::ValidationError naming the option.
std::vector<int> parse_teeth(const std::string& text, int teeth);
/// "50x100" → (50, 100), at most grinding::kMaxPointsPerFlank points. Throws CLI::ValidationError.
std::pair<int, int> parse_grid_size(const std::string& text);

/// How a command that prints ISO 1328-1 values reports them (docs/iso1328.md): --iso-direction transverse|normal
/// (default transverse, the standard's), --helix-slope-sign helix-angle|rise-towards-plus-z (default helix-angle).
void add_iso_options(CLI::App* cmd, workbench::IsoOptions& options);

} // namespace geartopo::app
