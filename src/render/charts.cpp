// Line and bar charts: input checks and ranges here, drawing in chart2d.cpp.

#include "geartopo/render/charts.hpp"
#include "detail/chart2d.hpp"
#include "detail/layout.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace geartopo::render {

namespace {

using detail::require;

/// Running [min, max] of finite values.
struct Extent {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return lo > hi; }
};

/// The axis range: the caller's fixed ends, the rest from the data (padded, rounded to ticks).
Range axis_range(const AxisSpec& axis, Extent e, double pad) {
  if (axis.min) e.add(*axis.min);
  if (axis.max) e.add(*axis.max);
  Range r = detail::nice_range(e.lo, e.hi, pad);
  if (axis.min) r.min = *axis.min;
  if (axis.max) r.max = *axis.max;
  require(r.max > r.min, "chart: axis '" + axis.title + "' has max <= min");
  return r;
}

/// Bands and reference lines widen the range they lie across (a tolerance band should be visible).
void add_decorations(const std::vector<Band>& bands, const std::vector<RefLine>& lines, Extent& x, Extent& y) {
  for (const Band& b : bands) {
    Extent& e = b.orientation == Orientation::horizontal ? y : x;
    e.add(b.from);
    e.add(b.to);
  }
  for (const RefLine& l : lines) (l.orientation == Orientation::horizontal ? y : x).add(l.at);
}

/// The legend's labels in the order the chart builder adds its entries: bands, bars, lines (named ones only).
std::vector<std::string> legend_labels(const std::vector<Band>& bands, const std::vector<BarSeries>& bars,
                                       const std::vector<Series>& lines) {
  std::vector<std::string> labels;
  for (const Band& b : bands)
    if (!b.label.empty()) labels.push_back(b.label);
  for (const BarSeries& b : bars)
    if (!b.name.empty()) labels.push_back(b.name);
  for (const Series& l : lines)
    if (!l.name.empty()) labels.push_back(l.name);
  return labels;
}

void check_series(const Series& s, const std::string& chart) {
  require(s.x.size() == s.y.size(), chart + ": series '" + s.name + "' has " + std::to_string(s.x.size()) +
                                        " x values but " + std::to_string(s.y.size()) + " y values");
}

} // namespace

RenderResult render_line_chart(const LineChart& chart, const std::filesystem::path& png) {
  Extent x;
  Extent y;
  for (const Series& s : chart.series) {
    check_series(s, "line chart");
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        x.add(s.x[i]);
        y.add(s.y[i]);
      }
  }
  require(!x.empty(), "line chart '" + chart.title + "': no data point (every series is empty or non-finite)");
  add_decorations(chart.bands, chart.lines, x, y);

  detail::ChartFrame frame;
  frame.title = chart.title;
  frame.x_label = detail::axis_label(chart.x.title, chart.x.unit);
  frame.y_label = detail::axis_label(chart.y.title, chart.y.unit);
  frame.x_range = axis_range(chart.x, x, 0.03);
  frame.y_range = axis_range(chart.y, y, 0.06);
  frame.size = chart.size;
  frame.px = detail::font_px(chart.size, chart.font_px);
  frame.legend = chart.legend;
  require(chart.x_tick_labels.empty() || chart.x_tick_labels.size() == chart.x_ticks.size(),
          "line chart '" + chart.title + "': " + std::to_string(chart.x_tick_labels.size()) + " tick labels for " +
              std::to_string(chart.x_ticks.size()) + " ticks");
  frame.x_ticks = chart.x_ticks;
  frame.x_tick_labels = chart.x_tick_labels;
  frame.legend_labels = legend_labels(chart.bands, {}, chart.series);

  detail::ChartBuilder builder(frame);
  for (const Band& b : chart.bands) builder.add_band(b);
  for (std::size_t i = 0; i < chart.series.size(); ++i)
    builder.add_line(chart.series[i], chart.series[i].colour.value_or(series_colour(i)));
  for (const RefLine& l : chart.lines) builder.add_ref_line(l);
  for (const Annotation& a : chart.annotations) builder.add_annotation(a);
  builder.set_text_block(chart.text);
  builder.render(png);
  return {std::nullopt, frame.x_range, frame.y_range};
}

RenderResult render_bar_chart(const BarChart& chart, const std::filesystem::path& png) {
  require(!chart.bars.empty(), "bar chart '" + chart.title + "': no bar series");
  const std::size_t n = chart.bars.front().values.size();
  require(n > 0, "bar chart '" + chart.title + "': no data point (the bar series are empty)");
  require(chart.categories.empty() || chart.categories.size() == n,
          "bar chart: " + std::to_string(chart.categories.size()) + " categories for " + std::to_string(n) + " bars");
  require(chart.x_positions.empty() || chart.x_positions.size() == n,
          "bar chart: " + std::to_string(chart.x_positions.size()) + " x positions for " + std::to_string(n) + " bars");
  std::vector<double> xs = chart.x_positions;
  if (xs.empty())
    for (std::size_t i = 0; i < n; ++i) xs.push_back(static_cast<double>(i + 1));
  for (std::size_t i = 1; i < xs.size(); ++i)
    require(xs[i] > xs[i - 1], "bar chart: x positions must increase strictly");

  Extent x;
  Extent y;
  y.add(0.0); // bars stand on zero
  for (const BarSeries& b : chart.bars) {
    require(b.values.size() == n, "bar chart: series '" + b.name + "' has " + std::to_string(b.values.size()) +
                                      " values, expected " + std::to_string(n));
    for (double v : b.values) {
      require(std::isfinite(v), "bar chart: series '" + b.name + "' has a non-finite value");
      y.add(v);
    }
  }
  double spacing = 1.0;
  if (xs.size() > 1) {
    spacing = xs[1] - xs[0];
    for (std::size_t i = 2; i < xs.size(); ++i) spacing = std::min(spacing, xs[i] - xs[i - 1]);
  }
  x.add(xs.front() - 0.6 * spacing);
  x.add(xs.back() + 0.6 * spacing);
  for (const Series& s : chart.lines) {
    check_series(s, "bar chart");
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        x.add(s.x[i]);
        y.add(s.y[i]);
      }
  }
  add_decorations(chart.bands, chart.ref_lines, x, y);

  detail::ChartFrame frame;
  frame.title = chart.title;
  frame.x_label = detail::axis_label(chart.x.title, chart.x.unit);
  frame.y_label = detail::axis_label(chart.y.title, chart.y.unit);
  frame.x_range = {chart.x.min.value_or(x.lo), chart.x.max.value_or(x.hi)};
  detail::require(frame.x_range.max > frame.x_range.min, "bar chart: x axis max <= min");
  frame.y_range = axis_range(chart.y, y, 0.06);
  frame.size = chart.size;
  frame.px = detail::font_px(chart.size, chart.font_px);
  frame.legend = chart.legend;
  frame.grid = true;
  if (!chart.categories.empty() || chart.x_positions.empty()) {
    // One tick per bar, thinned out when the labels would not fit side by side.
    double widest = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::string label = chart.categories.empty() ? std::to_string(i + 1) : chart.categories[i];
      widest = std::max(widest, detail::text_width_estimate(label, static_cast<int>(0.9 * frame.px)));
    }
    const double plot_w = chart.size.width - 8.0 * frame.px;
    const double per_bar = plot_w * spacing / (frame.x_range.max - frame.x_range.min);
    const std::size_t every =
        std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil((widest + 0.8 * frame.px) / per_bar)));
    for (std::size_t i = 0; i < n; i += every) {
      frame.x_ticks.push_back(xs[i]);
      frame.x_tick_labels.push_back(chart.categories.empty() ? std::to_string(i + 1) : chart.categories[i]);
    }
  }

  frame.legend_labels = legend_labels(chart.bands, chart.bars, chart.lines);

  detail::ChartBuilder builder(frame);
  for (const Band& b : chart.bands) builder.add_band(b);
  for (std::size_t i = 0; i < chart.bars.size(); ++i)
    builder.add_bars(xs, chart.bars[i].values, chart.bars[i].name, chart.bars[i].colour.value_or(series_colour(i)),
                     0.75);
  for (std::size_t i = 0; i < chart.lines.size(); ++i)
    builder.add_line(chart.lines[i], chart.lines[i].colour.value_or(series_colour(chart.bars.size() + i)));
  for (const RefLine& l : chart.ref_lines) builder.add_ref_line(l);
  for (const Annotation& a : chart.annotations) builder.add_annotation(a);
  builder.set_text_block(chart.text);
  builder.render(png);
  return {std::nullopt, frame.x_range, frame.y_range};
}

} // namespace geartopo::render
