// geartopo — the command line's shared pieces: the scene's Workbench (built by the scene library) and the parsers of
// the options that several commands take.
#pragma once

#include "geartopo/diagnosis/klingelnberg.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <string>
#include <utility>
#include <vector>

namespace CLI {
class App;
}

namespace geartopo::app {

using workbench::make_effects;
using workbench::Workbench;

/// "all" → {} (every tooth); "1,18" → {1, 18}. Throws CLI::ValidationError naming the option.
std::vector<int> parse_teeth(const std::string& text, int teeth);
/// "50x100" → (50, 100), at most grinding::kMaxPointsPerFlank points. Throws CLI::ValidationError.
std::pair<int, int> parse_grid_size(const std::string& text);

/// The Klingelnberg reader's options as flags of a command that reads measurements (docs/measurement-formats.md):
/// --mka-spacing roll-length|diameter, --mka-direction transverse|normal, --mka-signs raw|din.
void add_klingelnberg_options(CLI::App* cmd, diagnosis::KlingelnbergOptions& options);

} // namespace geartopo::app
