#pragma once
// Internal: a vtkChartXY on an off-screen context, fed with plain C++ primitives. Used by the line chart, the bar
// chart and the heat map. No VTK headers here.

#include "geartopo/render/charts.hpp"
#include "geartopo/render/common.hpp"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::render::detail {

struct ChartFrame {
  std::string title;
  std::string x_label;
  std::string y_label;
  Range x_range;
  Range y_range;
  ImageSize size;
  int px = 18;
  LegendPlace legend = LegendPlace::top_right;
  /// The legend's labels in drawing order, known before the series are added: with LegendPlace::above the layout
  /// reserves as many rows above the plot as they need at the image's width (empty: one row).
  std::vector<std::string> legend_labels;
  bool grid = true;
  /// Custom x tick positions and labels (categories); empty → nice ticks.
  std::vector<double> x_ticks;
  std::vector<std::string> x_tick_labels;
  /// A colour bar at the right edge (the chart leaves room for it).
  std::optional<Range> colour_bar;
  std::string colour_bar_label;
};

/// A rectangle in chart coordinates filled with one colour (heat-map cell).
struct ChartCell {
  double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0;
  Rgb colour;
  bool hatched = false;
  std::string text; ///< centred in the cell when it fits
  Rgb text_colour = colours::text;
};

/// A segment in chart coordinates (outline of marked cells).
struct ChartSegment {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
};

class ChartBuilder {
public:
  explicit ChartBuilder(const ChartFrame& frame);
  ~ChartBuilder();
  ChartBuilder(const ChartBuilder&) = delete;
  ChartBuilder& operator=(const ChartBuilder&) = delete;

  void add_band(const Band& band);
  void add_line(const Series& series, Rgb colour);
  /// Bars at x with heights y (several calls: side by side).
  void add_bars(const std::vector<double>& x, const std::vector<double>& y, const std::string& name, Rgb colour,
                double bar_width_fraction);
  void add_cells(std::vector<ChartCell> cells, int text_px);
  /// Thick outline segments; `label` (if any) goes into the legend with a hatched swatch.
  void add_outline(std::vector<ChartSegment> segments, const std::string& label);
  void add_ref_line(const RefLine& line);
  void add_annotation(const Annotation& annotation);
  void set_text_block(const TextBlock& block);

  /// Draws everything and writes the PNG. Call once.
  void render(const std::filesystem::path& png);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace geartopo::render::detail
