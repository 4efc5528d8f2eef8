// Line and bar charts: rendered without a display, requested size, not blank, the series actually drawn.

#include "geartopo/render/charts.hpp"
#include "geartopo/render/image.hpp"
#include "render_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace geartopo::render {
namespace {

LineChart profile_chart() {
  LineChart c;
  c.title = "Profile deviation, left flank, tooth 1";
  c.x = {"roll length ξ", "mm", {}, {}};
  c.y = {"deviation", "µm", {}, {}};
  Series measured{"measured", {}, {}, Rgb{31, 119, 180}, 2.5, Marker::none, 7.0, false};
  Series mean{"mean profile", {}, {}, Rgb{214, 39, 40}, 2.0, Marker::circle, 7.0, true};
  for (int i = 0; i <= 200; ++i) {
    const double x = 5.0 + 0.1 * i;
    measured.x.push_back(x);
    measured.y.push_back(3.0 * std::sin(0.7 * x) + 0.4 * std::sin(5.0 * x));
    if (i % 20 == 0) {
      mean.x.push_back(x);
      mean.y.push_back(0.3 * (x - 15.0));
    }
  }
  c.series = {measured, mean};
  c.bands = {{Orientation::horizontal, -5.0, 5.0, colours::tolerance, 0.22, "tolerance ±5 µm"},
             {Orientation::vertical, 8.0, 22.0, {150, 150, 220}, 0.15, "evaluation range"}};
  c.lines = {{Orientation::vertical, 8.0, colours::grey, 1.5, true, "start of evaluation"}};
  c.annotations = {{16.0, -4.0, "fHα = 1.8 µm", colours::text, HAlign::left}};
  c.text = {Corner::top_left, {"Fα 3.2 µm  class 4", "ffα 2.1 µm  class 5", "fHα −1.4 µm"}};
  c.size = {900, 600};
  return c;
}

TEST(LineChart, RendersWithoutDisplayAtTheRequestedSize) {
  const LineChart c = profile_chart();
  const auto png = test::output("line_chart.png");
  testing::internal::CaptureStderr();
  const RenderResult r = render_line_chart(c, png);
  const std::string log = testing::internal::GetCapturedStderr();
  EXPECT_EQ(log, "") << "VTK complained (e.g. GLEW could not be initialized: is glewInit exported?)";
  test::expect_figure(png, c.size);
  // Axis ranges cover the data and the tolerance band.
  ASSERT_TRUE(r.x_range && r.y_range);
  EXPECT_LE(r.x_range->min, 5.0);
  EXPECT_GE(r.x_range->max, 25.0);
  EXPECT_LE(r.y_range->min, -5.0);
  EXPECT_GE(r.y_range->max, 5.0);
  EXPECT_FALSE(r.colour_range);
  // Both series are drawn in their colours.
  const Image img = read_png(png);
  EXPECT_TRUE(contains_colour(img, {31, 119, 180}, 12, 200));
  EXPECT_TRUE(contains_colour(img, {214, 39, 40}, 12, 50));
}

TEST(LineChart, FixedAxisRangesAreKept) {
  LineChart c = profile_chart();
  c.x.min = 0.0;
  c.x.max = 30.0;
  c.y.min = -10.0;
  c.y.max = 10.0;
  const RenderResult r = render_line_chart(c, test::output("line_chart_fixed.png"));
  EXPECT_EQ(*r.x_range, (Range{0.0, 30.0}));
  EXPECT_EQ(*r.y_range, (Range{-10.0, 10.0}));
}

TEST(LineChart, MeasuringMachineLayoutTraceRunsUpwards) {
  // Deviation horizontal, position vertical: the caller passes (deviation, position) as (x, y).
  LineChart c;
  c.title = "Helix trace";
  c.x = {"deviation", "µm", -10.0, 10.0};
  c.y = {"face width", "mm", {}, {}};
  Series trace{"tooth 1", {}, {}, Rgb{20, 70, 200}, 2.0, Marker::none, 7.0, false};
  for (int i = 0; i <= 100; ++i) {
    trace.y.push_back(0.3 * i);
    trace.x.push_back(2.0 * std::sin(0.2 * i));
  }
  c.series = {trace};
  c.bands = {{Orientation::vertical, -4.0, 4.0, colours::tolerance, 0.22, "±4 µm"}};
  c.legend = LegendPlace::above;
  c.size = {500, 800};
  const auto png = test::output("line_chart_vertical.png");
  const RenderResult r = render_line_chart(c, png);
  test::expect_figure(png, c.size);
  EXPECT_LE(r.y_range->min, 0.0);
  EXPECT_GE(r.y_range->max, 30.0);
  EXPECT_TRUE(contains_colour(read_png(png), {20, 70, 200}, 12, 200));
}

TEST(BarChart, PitchBarsWithCumulativeLine) {
  BarChart c;
  c.title = "Single and cumulative pitch deviation";
  c.x = {"tooth", "", {}, {}};
  c.y = {"deviation", "µm", {}, {}};
  BarSeries fp{"single pitch fp", {}, Rgb{31, 119, 180}};
  Series Fp{"cumulative pitch Fp", {}, {}, Rgb{0, 0, 0}, 2.0, Marker::circle, 7.0, false};
  double sum = 0.0;
  for (int i = 0; i < 31; ++i) {
    const double v = 2.5 * std::sin(0.9 * i) + 0.8 * std::cos(2.1 * i);
    fp.values.push_back(v);
    sum += v;
    Fp.x.push_back(i + 1);
    Fp.y.push_back(sum);
  }
  c.bars = {fp};
  c.lines = {Fp};
  c.ref_lines = {{Orientation::horizontal, 4.0, {200, 0, 0}, 1.5, true, "+fp,T"},
                 {Orientation::horizontal, -4.0, {200, 0, 0}, 1.5, true, "−fp,T"}};
  c.size = {1000, 500};
  const auto png = test::output("bar_chart.png");
  const RenderResult r = render_bar_chart(c, png);
  test::expect_figure(png, c.size);
  EXPECT_LE(r.y_range->min, -4.0);
  EXPECT_GE(r.y_range->max, 6.0);
  const Image img = read_png(png);
  EXPECT_TRUE(contains_colour(img, {31, 119, 180}, 6, 2000)); // the bars
}

TEST(BarChart, CategoriesAndTwoSeriesSideBySide) {
  BarChart c;
  c.title = "Deviations per flank";
  c.y = {"deviation", "µm", {}, {}};
  c.categories = {"Fα", "ffα", "fHα", "Fβ", "ffβ", "fHβ"};
  c.bars = {{"left", {3.2, 2.1, -1.4, 4.0, 1.5, 2.2}, Rgb{31, 119, 180}},
            {"right", {2.8, 1.9, 1.1, 3.5, 1.2, -2.5}, Rgb{255, 127, 14}}};
  c.size = {800, 500};
  const auto png = test::output("bar_chart_categories.png");
  render_bar_chart(c, png);
  test::expect_figure(png, c.size);
  const Image img = read_png(png);
  EXPECT_TRUE(contains_colour(img, {31, 119, 180}, 6, 1000));
  EXPECT_TRUE(contains_colour(img, {255, 127, 14}, 6, 1000));
}

TEST(BarChart, ALegendAboveTooWideForOneRowWrapsInsideTheImage) {
  // Six entries with long labels at 800 px: one row would run off the image's left edge (the first entries lost);
  // wrapped, every entry's symbol is drawn above the plot area.
  BarChart c;
  c.title = "Legend above, wrapped";
  c.y = {"deviation", "µm", 0.0, 10.0};
  c.categories = {"A", "B", "C"};
  c.bars = {{"the bars' median over every sample", {1.0, 1.5, 1.2}, Rgb{200, 200, 200}}};
  const std::vector<Rgb> colours{{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {148, 103, 189}, {255, 127, 14}};
  for (std::size_t i = 0; i < colours.size(); ++i)
    c.lines.push_back({"series number " + std::to_string(i + 1) + " with a long legend label", {1.0, 3.0}, {0.5, 1.0},
                       colours[i], 3.0, Marker::none, 7.0, false});
  c.legend = LegendPlace::above;
  c.size = {800, 500};
  const auto png = test::output("bar_chart_wrapped_legend.png");
  render_bar_chart(c, png);
  test::expect_figure(png, c.size);
  const Image img = read_png(png);
  // The top quarter holds the title and the legend only (the data stay below y = 1.5 of 0 … 10).
  Image top{img.width, img.height / 4, {img.pixels.begin(), img.pixels.begin() + img.width * (img.height / 4)}};
  for (const Rgb& colour : colours) EXPECT_TRUE(contains_colour(top, colour, 6, 20)) << int(colour.r);
  EXPECT_TRUE(contains_colour(top, {200, 200, 200}, 6, 100)); // the bars' entry, first in the legend
}

} // namespace
} // namespace geartopo::render
