#pragma once
// 2D charts → PNG: line chart and bar chart (docs/rendering.md). Plain C++: no VTK here.

#include "geartopo/render/common.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace geartopo::render {

enum class Marker { none, circle, square, diamond, cross, plus };
enum class Orientation {
  horizontal, ///< a band or line at constant y, across the whole x range
  vertical,   ///< a band or line at constant x, across the whole y range
};
/// Legend position: inside a corner of the plot area, or `above` it (one row, right-aligned, never covers data).
enum class LegendPlace { none, top_left, top_right, bottom_left, bottom_right, above };

/// One polyline. NaN in x or y breaks the line. Unset colour → series_colour(index).
struct Series {
  std::string name; ///< legend entry; empty → not in the legend
  std::vector<double> x;
  std::vector<double> y;
  std::optional<Rgb> colour;
  double width = 2.0; ///< px
  Marker marker = Marker::none;
  double marker_size = 7.0; ///< px
  bool dashed = false;
};

/// A shaded band between `from` and `to` (e.g. a tolerance band ±T, an evaluation range [a, b]).
struct Band {
  Orientation orientation = Orientation::horizontal;
  double from = 0.0;
  double to = 0.0;
  Rgb colour = colours::tolerance;
  double opacity = 0.22;
  std::string label; ///< legend entry; empty → not in the legend
};

/// A straight marker line at `at`; `label` is written next to it (at the top / right end).
struct RefLine {
  Orientation orientation = Orientation::horizontal;
  double at = 0.0;
  Rgb colour = colours::grey;
  double width = 1.5;
  bool dashed = true;
  std::string label;
};

/// Free text anchored at (x, y) in chart (data) coordinates, vertically centred on y.
struct Annotation {
  double x = 0.0;
  double y = 0.0;
  std::string text;
  Rgb colour = colours::text;
  HAlign align = HAlign::left;
};

/// A block of text lines in a corner of the plot area, on a white box (e.g. "Fα 3.2 µm  class 4").
struct TextBlock {
  Corner corner = Corner::top_left;
  std::vector<std::string> lines;
};

/// Line chart. For the gear-measuring-machine layout (deviation horizontal, trace running upwards) pass the
/// series as (x = deviation, y = position) and use vertical bands for tolerances; nothing else is needed.
struct LineChart {
  std::string title;
  AxisSpec x;
  AxisSpec y;
  std::vector<Series> series;
  std::vector<Band> bands;    ///< drawn under the series
  std::vector<RefLine> lines; ///< drawn over the series
  std::vector<Annotation> annotations;
  TextBlock text;
  LegendPlace legend = LegendPlace::top_right;
  ImageSize size;
  int font_px = 0; ///< base font size; 0 = from the image size
  /// Custom x ticks (e.g. whole steps, or mirrored deviation labels); empty → nice ticks. Labels pair with positions.
  std::vector<double> x_ticks;
  std::vector<std::string> x_tick_labels;
};

/// Renders `chart` to `png`. Axis ranges not fixed by the caller cover the series, bands and lines, padded and
/// rounded to ticks. Throws std::invalid_argument for no finite data point or x/y of different lengths,
/// std::runtime_error when rendering or writing fails. Returns the axis ranges used.
RenderResult render_line_chart(const LineChart& chart, const std::filesystem::path& png);

/// One bar series: one value per category / x position. Unset colour → series_colour(index).
struct BarSeries {
  std::string name;
  std::vector<double> values;
  std::optional<Rgb> colour;
};

/// Bar chart, e.g. single pitch deviations as bars with the cumulative pitch as an overlaid line.
/// Bars stand at x = 1, 2, … n (labelled with `categories` when given) or at the numeric `x` when given.
/// Several bar series are drawn side by side. Line series use the same x coordinates.
struct BarChart {
  std::string title;
  AxisSpec x;
  AxisSpec y;
  std::vector<std::string> categories;
  std::vector<double> x_positions;
  std::vector<BarSeries> bars;
  std::vector<Series> lines;
  std::vector<Band> bands;
  std::vector<RefLine> ref_lines;
  std::vector<Annotation> annotations;
  TextBlock text;
  LegendPlace legend = LegendPlace::top_right;
  ImageSize size;
  int font_px = 0;
};

/// Renders `chart` to `png`. Throws std::invalid_argument when there is no bar, a series length differs from the
/// number of categories / positions, or a value is not finite; std::runtime_error when rendering or writing fails.
RenderResult render_bar_chart(const BarChart& chart, const std::filesystem::path& png);

} // namespace geartopo::render
