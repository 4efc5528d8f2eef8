#include "render_test_support.hpp"

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

TEST(RenderEnvironment, RunsWithoutADisplay) {
  EXPECT_TRUE(display_unset);
  EXPECT_EQ(std::getenv("DISPLAY"), nullptr);
}

} // namespace geartopo::render::test
