#pragma once
// Topology grid view (as in gear papers' topology figures) → PNG (docs/rendering.md).

#include "geartopo/render/common.hpp"

#include <Eigen/Core>

#include <filesystem>
#include <string>

namespace geartopo::render {

enum class GridOffset {
  height,   ///< deviation drawn as a height above the (u, v) plane, oblique 3D view
  in_plane, ///< deviation drawn as an offset along v, top view
};

/// rows × cols nodes: u (mm, drawn along x; e.g. axial position), v (mm, drawn along y; e.g. roll length or
/// diameter) and the deviation (µm) of each node. Row i, column j is one node; rows run along u.
struct GridTopology {
  std::string title;
  Eigen::MatrixXd u;
  Eigen::MatrixXd v;
  Eigen::MatrixXd deviation;
  AxisSpec u_axis{"face width", "mm", {}, {}}; ///< only title/unit are used
  AxisSpec v_axis{"roll length", "mm", {}, {}};
  GridOffset offset = GridOffset::height;
  /// Shown offset (mm) = deviation (µm) × 1e-3 × magnification. 0 = automatic (a round number such that the
  /// largest |deviation| is about 15 % of the grid's size in 3D, or 80 % of a row spacing in plane).
  double magnification = 0.0;
  bool show_values = true; ///< deviation written at the nodes
  int value_every = 1;      ///< values at every n-th row and column only (rows/cols 0, n, 2n, …): less crowding
  int value_decimals = 1;
  bool fill = true;            ///< colour the actual grid's surface with the colour map (the nodes are coloured anyway)
  double azimuth_deg = -30.0;  ///< 3D view: rotation of the view about the deviation axis (0: looking along +v)
  double elevation_deg = 40.0; ///< 3D view: angle of the view above the (u, v) plane
  ColourScale scale;
  ImageSize size;
  int font_px = 0;
};

/// Renders `grid` to `png`; returns the colour range used. Throws std::invalid_argument for an empty grid,
/// mismatched sizes, fewer than 2 rows or columns, or non-finite values; std::runtime_error when rendering or
/// writing fails.
RenderResult render_grid_topology(const GridTopology& grid, const std::filesystem::path& png);

/// The magnification actually used for `grid` (its own, or the automatic one).
double grid_magnification(const GridTopology& grid);

} // namespace geartopo::render
