// geartopo — the flank topology the simulator predicts: the 7×9 grid, dense profile and helix traces, and an
// optional dense grid, for every requested tooth and both flanks (docs/grinding.md, docs/conventions.md).
//
// Grid rows 1..R run from root to tip at diameters evenly spaced in roll length over the profile evaluation range L_α
// (ends included); columns 1..C run from the datum face over the helix evaluation range L_β (ends included).
// Profile traces run over the whole active profile at mid face width; helix traces over the whole face width at the
// middle of L_α. Deviations in µm along the flank normal, plus material positive.
#pragma once

#include "geartopo/core/flank.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/grinding/grinding_setup.hpp"

#include <functional>
#include <vector>

namespace geartopo::grinding {

struct GridPoint {
  int row = 0, col = 0; ///< 1-based: row from root to tip, col from the datum face
  double roll_length_mm = 0.0, diameter_mm = 0.0, z_mm = 0.0;
  double deviation_um = 0.0; ///< from the design (FlankDeviation::at)
  double design_um = 0.0;    ///< the design there (FormWheel::design(); 0: the bare involute)
};

struct TracePoint {
  double roll_length_mm = 0.0, diameter_mm = 0.0, z_mm = 0.0;
  double deviation_um = 0.0; ///< from the design
  int line = 0; ///< 1-based line in the traces file it was read from (0 when simulated)
  double design_um = 0.0;    ///< the design there
};

struct FlankTopology {
  int tooth = 1;
  geartopo::Flank flank = geartopo::Flank::Left;
  std::vector<GridPoint> grid;  ///< rows × cols, row-major
  std::vector<TracePoint> profile, helix;
  std::vector<GridPoint> dense; ///< empty unless requested
};

/// Largest grid (7×9 + dense) a flank may have: 4·10⁶ points, about 100 MB per flank of results.
inline constexpr long long kMaxPointsPerFlank = 4'000'000;
/// Largest number of points one simulation may compute over all flanks (memory stays under a few GB).
inline constexpr long long kMaxPointsPerSimulation = 100'000'000;

struct SimulationOptions {
  Method method = Method::Exact;
  std::vector<int> teeth;        ///< empty: all teeth
  int rows = 7, cols = 9;        ///< the topological grid
  int profile_points = 100, helix_points = 150;
  int dense_rows = 0, dense_cols = 0; ///< 0: no dense grid
  int threads = 0;               ///< 0: all hardware threads
  /// Called after each flank with (flanks done, flanks in all), from the worker threads: must be thread-safe and
  /// cheap. For progress display only; the result does not depend on it.
  std::function<void(long long, long long)> progress;
  /// Called within each flank (before every grid row and each trace), from the worker threads: an exception it throws
  /// stops the simulation and leaves simulate_topology (a Ctrl-C check: a flank of a fine grid takes minutes, far
  /// longer than a progress report apart). Must be thread-safe and cheap; the result does not depend on it.
  std::function<void()> keep_going;
};

/// Where a simulation evaluates (the layout described at the top of this file): the teeth, the grid's roll lengths
/// (rows) and axial positions (cols), the profile traces' roll lengths at profile_z_mm, the helix traces' axial
/// positions at helix_roll_length_mm, and the dense grid's rows and cols (empty unless requested). Throws
/// std::invalid_argument as simulate_topology does.
struct SimulationPoints {
  std::vector<int> teeth;
  std::vector<double> rows, cols, profile_roll_lengths, helix_z, dense_rows, dense_cols;
  double profile_z_mm = 0.0, helix_roll_length_mm = 0.0;
};
SimulationPoints simulation_points(const GrindingSetup& setup, const SimulationOptions& options);

/// One entry per requested tooth and flank, ordered by tooth then left, right. Throws std::runtime_error naming the
/// first point (in that order) the wheel never reaches (grinding::require_reached), std::invalid_argument for a
/// tooth outside 1..z, grids below 2×2, or more points than kMaxPointsPerFlank / kMaxPointsPerSimulation.
std::vector<FlankTopology> simulate_topology(const GrindingSetup& setup, const GrindingProcess& process,
                                             const SimulationOptions& options);

/// Throws std::runtime_error (require_reached) at the first point, in the topology's order, the wheel never reached.
void require_all_reached(const std::vector<FlankTopology>& topo);
/// Sets every point's design_um from `design` (the simulators call it on what they return).
void attach_design(std::vector<FlankTopology>& topo, const gears::FlankDesign& design);

/// Largest |deviation| (µm) over the grids of all flanks.
double largest_abs_deviation_um(const std::vector<FlankTopology>& topo);

/// Roll lengths of the grid rows / axial positions of the grid columns (evenly spaced, ends included).
std::vector<double> grid_roll_lengths(const gears::EvaluationRanges& r, int rows);
std::vector<double> grid_axial_positions(const gears::EvaluationRanges& r, int cols);

} // namespace geartopo::grinding
