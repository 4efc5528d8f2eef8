// Heat map: cells, values and marked-region outline computed here; drawing in chart2d.cpp.

#include "geartopo/render/heat_map.hpp"
#include "geartopo/render/colour_map.hpp"
#include "detail/chart2d.hpp"
#include "detail/layout.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace geartopo::render {

namespace {

using detail::require;

/// Cell centres → cell edges (midpoints; the outer edges half a spacing out). Centres must be strictly monotone.
std::vector<double> cell_edges(std::vector<double> centres, Eigen::Index n, const std::string& name) {
  if (centres.empty())
    for (Eigen::Index i = 0; i < n; ++i) centres.push_back(static_cast<double>(i + 1));
  require(static_cast<Eigen::Index>(centres.size()) == n,
          "heat map: " + std::to_string(centres.size()) + " " + name + " centres for " + std::to_string(n) + " cells");
  for (double c : centres) require(std::isfinite(c), "heat map: non-finite " + name + " centre");
  const double sign = centres.size() > 1 && centres[1] < centres[0] ? -1.0 : 1.0;
  for (std::size_t i = 1; i < centres.size(); ++i)
    require(sign * (centres[i] - centres[i - 1]) > 0.0, "heat map: " + name + " centres must be strictly monotone");
  std::vector<double> edges(centres.size() + 1);
  for (std::size_t i = 1; i < centres.size(); ++i) edges[i] = 0.5 * (centres[i - 1] + centres[i]);
  const double first = centres.size() > 1 ? centres[1] - centres[0] : 1.0;
  const double last = centres.size() > 1 ? centres.back() - centres[centres.size() - 2] : 1.0;
  edges.front() = centres.front() - 0.5 * first;
  edges.back() = centres.back() + 0.5 * last;
  return edges;
}

/// Relative luminance (sRGB approximated by gamma 2.2) — chooses black or white text on a cell.
double luminance(Rgb c) {
  const auto lin = [](std::uint8_t v) { return std::pow(v / 255.0, 2.2); };
  return 0.2126 * lin(c.r) + 0.7152 * lin(c.g) + 0.0722 * lin(c.b);
}

} // namespace

RenderResult render_heat_map(const HeatMap& map, const std::filesystem::path& png) {
  const Eigen::Index rows = map.values.rows();
  const Eigen::Index cols = map.values.cols();
  require(rows > 0 && cols > 0, "heat map '" + map.title + "': no data point (empty grid)");
  const bool has_mask = map.marked.size() > 0;
  require(!has_mask || (map.marked.rows() == rows && map.marked.cols() == cols),
          "heat map: the marked-cell mask is " + std::to_string(map.marked.rows()) + " x " +
              std::to_string(map.marked.cols()) + ", the grid " + std::to_string(rows) + " x " + std::to_string(cols));
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) {
      const double v = map.values(i, j);
      require(!std::isinf(v), "heat map: infinite value");
      if (std::isnan(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  require(lo <= hi, "heat map '" + map.title + "': no data point (every value is NaN)");
  const Range colour = colour_range(lo, hi, map.scale);
  const std::vector<double> xe = cell_edges(map.x_centres, cols, "x");
  const std::vector<double> ye = cell_edges(map.y_centres, rows, "y");

  detail::ChartFrame frame;
  frame.title = map.title;
  frame.x_label = detail::axis_label(map.x.title, map.x.unit);
  frame.y_label = detail::axis_label(map.y.title, map.y.unit);
  frame.x_range = {std::min(xe.front(), xe.back()), std::max(xe.front(), xe.back())};
  frame.y_range = {std::min(ye.front(), ye.back()), std::max(ye.front(), ye.back())};
  frame.size = map.size;
  frame.px = detail::font_px(map.size, map.font_px);
  frame.legend = map.marked_label.empty() ? LegendPlace::none : LegendPlace::above;
  frame.grid = false;
  frame.colour_bar = colour;
  frame.colour_bar_label = detail::axis_label(map.scale.title, map.scale.unit);
  if (map.x_centres.empty()) // index axes: a tick per cell, every k-th one for more than 12 columns
    for (Eigen::Index j = 0; j < cols; j += std::max<Eigen::Index>(1, cols / 12)) {
      frame.x_ticks.push_back(static_cast<double>(j + 1));
      frame.x_tick_labels.push_back(std::to_string(j + 1));
    }

  std::vector<detail::ChartCell> cells;
  cells.reserve(static_cast<std::size_t>(rows * cols));
  const auto marked = [&](Eigen::Index i, Eigen::Index j) {
    return has_mask && i >= 0 && j >= 0 && i < rows && j < cols && map.marked(i, j);
  };
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) {
      detail::ChartCell c;
      c.x0 = xe[static_cast<std::size_t>(j)];
      c.x1 = xe[static_cast<std::size_t>(j + 1)];
      c.y0 = ye[static_cast<std::size_t>(i)];
      c.y1 = ye[static_cast<std::size_t>(i + 1)];
      const double v = map.values(i, j);
      c.colour = std::isnan(v) ? colours::light_grey : colour_for(v, colour);
      c.hatched = map.hatch_marked && marked(i, j);
      if (map.show_values && !std::isnan(v)) c.text = detail::format_value(v, map.value_decimals);
      c.text_colour = luminance(c.colour) < 0.25 ? colours::white : colours::text;
      cells.push_back(c);
    }
  // Outline of the marked region: the cell edges between a marked and an unmarked cell (or the border).
  std::vector<detail::ChartSegment> outline;
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) {
      if (!marked(i, j)) continue;
      const double x0 = xe[static_cast<std::size_t>(j)], x1 = xe[static_cast<std::size_t>(j + 1)];
      const double y0 = ye[static_cast<std::size_t>(i)], y1 = ye[static_cast<std::size_t>(i + 1)];
      if (!marked(i - 1, j)) outline.push_back({x0, y0, x1, y0});
      if (!marked(i + 1, j)) outline.push_back({x0, y1, x1, y1});
      if (!marked(i, j - 1)) outline.push_back({x0, y0, x0, y1});
      if (!marked(i, j + 1)) outline.push_back({x1, y0, x1, y1});
    }

  detail::ChartBuilder builder(frame);
  builder.add_cells(std::move(cells), static_cast<int>(std::lround(0.8 * frame.px)));
  if (!outline.empty() || !map.marked_label.empty()) builder.add_outline(std::move(outline), map.marked_label);
  builder.render(png);
  return {colour, frame.x_range, frame.y_range};
}

} // namespace geartopo::render
