#pragma once
// Heat map of a rows × cols grid of values (e.g. a residual map) → PNG (docs/rendering.md).

#include "geartopo/render/common.hpp"

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace geartopo::render {

/// values(i, j) is the cell of row i (y) and column j (x). Row 0 is at the bottom. NaN = no data (grey cell).
struct HeatMap {
  std::string title;
  AxisSpec x; ///< fixed min/max are ignored: the axes span the cells
  AxisSpec y;
  Eigen::MatrixXd values;
  std::vector<double> x_centres; ///< cols cell centres, strictly monotone; empty → 1 … cols
  std::vector<double> y_centres; ///< rows cell centres, strictly monotone; empty → 1 … rows
  /// Marked cells (e.g. failing regions), rows × cols or empty: the outline of the marked region is drawn thick
  /// black, and the cells are hatched when `hatch_marked`.
  Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> marked;
  bool hatch_marked = true;
  std::string marked_label; ///< legend text for the marked cells (e.g. "outside tolerance"); empty → none
  bool show_values = true;  ///< value written in each cell when it fits
  int value_decimals = 1;
  ColourScale scale;
  ImageSize size;
  int font_px = 0;
};

/// Renders `map` to `png`; returns the colour range used and the axis ranges.
/// Throws std::invalid_argument for an empty grid, no finite value, or sizes that do not match;
/// std::runtime_error when rendering or writing fails.
RenderResult render_heat_map(const HeatMap& map, const std::filesystem::path& png);

} // namespace geartopo::render
