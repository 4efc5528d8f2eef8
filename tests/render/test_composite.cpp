// Composite of PNGs (no OpenGL needed) and rendering from several threads.

#include "geartopo/render/charts.hpp"
#include "geartopo/render/composite.hpp"
#include "geartopo/render/image.hpp"
#include "render_test_support.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace geartopo::render {
namespace {

std::filesystem::path panel(const std::string& name, int w, int h, Rgb c) {
  Image img;
  img.width = w;
  img.height = h;
  img.pixels.assign(static_cast<std::size_t>(w) * h, c);
  const auto path = test::output(name);
  write_png(img, path);
  return path;
}

TEST(Composite, PanelsSideBySideWithCaptions) {
  Composite c;
  c.title = "Before | after";
  c.panels = {{panel("panel_red.png", 300, 200, {220, 40, 40}), "before"},
              {panel("panel_blue.png", 240, 260, {40, 40, 220}), "after"}};
  c.gap_px = 10;
  c.font_px = 16;
  const auto png = test::output("composite.png");
  const ImageSize size = render_composite(c, png);
  const Image img = read_png(png);
  EXPECT_EQ(img.width, size.width);
  EXPECT_EQ(img.height, size.height);
  EXPECT_EQ(size.width, 2 * 300 + 3 * 10); // cells as large as the largest panel
  EXPECT_GT(size.height, 260 + 2 * 10);    // + title and captions
  EXPECT_EQ(count_colour(img, {220, 40, 40}, 0), 300U * 200U);
  EXPECT_EQ(count_colour(img, {40, 40, 220}, 0), 240U * 260U);
  EXPECT_GT(count_colour(img, colours::text, 60), 100U) << "title and captions";
}

TEST(Composite, GridOfFourPanels) {
  Composite c;
  for (int k = 0; k < 4; ++k)
    c.panels.push_back({panel("panel_" + std::to_string(k) + ".png", 100, 80, {0, 150, 0}), ""});
  c.columns = 2;
  c.gap_px = 0;
  const auto png = test::output("composite_grid.png");
  const ImageSize size = render_composite(c, png);
  EXPECT_EQ(size.width, 200);
  EXPECT_EQ(size.height, 160);
  EXPECT_EQ(count_colour(read_png(png), {0, 150, 0}, 0), 4U * 100U * 80U);
}

TEST(Threads, RenderCallsFromSeveralThreadsTakeTurnsOnTheOneContext) {
  std::vector<std::filesystem::path> paths;
  for (int k = 0; k < 3; ++k) paths.push_back(test::output("thread_" + std::to_string(k) + ".png"));
  const auto render = [&paths](int k) {
    LineChart c;
    c.title = "thread " + std::to_string(k);
    c.series = {{"s", {0.0, 1.0, 2.0, 3.0}, {0.0, 1.0, 0.5, 2.0}, {}, 3.0, Marker::none, 7.0, false}};
    c.size = {400, 300};
    render_line_chart(c, paths[static_cast<std::size_t>(k)]);
  };
  std::thread a(render, 0);
  std::thread b(render, 1);
  render(2);
  a.join();
  b.join();
  for (const auto& p : paths) test::expect_figure(p, {400, 300}, 50.0, 0.01);
}

} // namespace
} // namespace geartopo::render
