#include "render_test_support.hpp"

#include "geartopo/render/charts.hpp"

#include <gtest/gtest.h>

#include <cstdlib>

namespace geartopo::render::test {

namespace {
/// No display for any test: runs before main (ctest unsets DISPLAY too, see CMakeLists.txt).
const bool display_unset = [] {
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  return true;
}();
} // namespace

std::filesystem::path output(const std::string& name) {
  const std::filesystem::path dir(GEARTOPO_RENDER_TEST_OUTPUT);
  std::filesystem::create_directories(dir);
  const std::filesystem::path p = dir / name;
  std::filesystem::remove(p);
  return p;
}

void expect_figure(const std::filesystem::path& png, ImageSize size, double min_variance, double min_share) {
  ASSERT_TRUE(std::filesystem::exists(png)) << png;
  const ImageStats s = image_stats(png);
  EXPECT_EQ(s.width, size.width) << png;
  EXPECT_EQ(s.height, size.height) << png;
  EXPECT_GT(s.variance, min_variance) << png;
  EXPECT_GT(s.non_background_share, min_share) << png;
}

// Every render test runs with DISPLAY unset; this one points DISPLAY at an X server that does not exist. A renderer
// that tried X (VTK's default on Linux) would fail or abort here; the EGL off-screen path must not care.
TEST(RenderEnvironment, IgnoresADisplayThatDoesNotExist) {
  ASSERT_TRUE(display_unset);
  setenv("DISPLAY", ":97", 1);
  LineChart c;
  c.title = "display check";
  c.series = {Series{"line", {0.0, 1.0, 2.0}, {0.0, 2.0, 1.0}, Rgb{31, 119, 180}, 3.0, Marker::none, 7.0, false}};
  c.size = {400, 300};
  const auto png = output("display_check.png");
  (void)render_line_chart(c, png);
  unsetenv("DISPLAY");
  expect_figure(png, c.size, 10.0, 0.001);
}

} // namespace geartopo::render::test
