// geartopo — the command line's shared pieces: the scene's Workbench (built by the scene library) and the parsers of
// the options that several commands take.
#pragma once

#include "geartopo/diagnosis/klingelnberg.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <string>
#include <utility>
#include <vector>

namespace CLI {
class App;
class Validator;
}

namespace geartopo::app {

/// A number within [lo, hi] and finite: CLI::Range lets NaN through (every comparison with NaN is false), so
/// `--noise-um nan` or `--step nan` passed the check. Refuses NaN, ±inf and values outside the range (exit 2).
CLI::Validator finite_in(double lo, double hi);
/// A path that is not empty: `--out ""` wrote into the current folder's root ("" / "file" is "file"; "" as a folder
/// was created as nothing) instead of being refused.
CLI::Validator non_empty_path();
/// A whole number ≥ 0 written with digits only: CLI11 reads "-1" into an unsigned seed as 2⁶⁴ − 1.
CLI::Validator digits_only();

using workbench::make_effects;
using workbench::Workbench;

/// When compensation made the gear worse — the largest |deviation| after is above the one before by more than
/// kWorseToleranceUm — the sentence to warn with (stderr and iso1328.json "warnings"); otherwise empty. E.g. the paper
/// method cancels a rotation that does not touch the flank (ε_yy, ε_ya) through the other axes and spoils the gear.
inline constexpr double kWorseToleranceUm = 0.01; ///< far below any tolerance, far above the simulation's rounding
std::string compensation_made_worse(double before_um, double after_um);

/// Before a long simulation (at least kEstimateFromPoints points), when stderr is a terminal: one line with the
/// number of points and flanks and the expected wall time at the rates of docs/performance.md (exact ≈ 260 k,
/// linear ≈ 1.7 M points/s on 2 cores). Nothing for scripts (stderr not a terminal), so their logs stay the same.
inline constexpr long long kEstimateFromPoints = 1'000'000;
void print_work_estimate(long long points, long long flanks, bool exact);

/// "all" → {} (every tooth); "1,18" → {1, 18}. Throws CLI::ValidationError naming the option.
std::vector<int> parse_teeth(const std::string& text, int teeth);
/// "50x100" → (50, 100), at most grinding::kMaxPointsPerFlank points. Throws CLI::ValidationError.
std::pair<int, int> parse_grid_size(const std::string& text);

/// The Klingelnberg reader's options as flags of a command that reads measurements (docs/measurement-formats.md):
/// --mka-spacing roll-length|diameter, --mka-direction transverse|normal, --mka-signs raw|din.
void add_klingelnberg_options(CLI::App* cmd, diagnosis::KlingelnbergOptions& options);

/// How a command that prints ISO 1328-1 values reports them (docs/iso1328.md): --iso-direction transverse|normal
/// (default transverse, the standard's), --helix-slope-sign helix-angle|rise-towards-plus-z (default helix-angle).
void add_iso_options(CLI::App* cmd, workbench::IsoOptions& options);

} // namespace geartopo::app
