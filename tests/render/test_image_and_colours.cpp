// Image helpers and the colour map: no OpenGL needed.

#include "geartopo/render/colour_map.hpp"
#include "geartopo/render/image.hpp"
#include "render_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace geartopo::render {
namespace {

Image uniform(int w, int h, Rgb c) {
  Image img;
  img.width = w;
  img.height = h;
  img.pixels.assign(static_cast<std::size_t>(w) * h, c);
  return img;
}

TEST(ImageStats, BlankImageHasNoVarianceAndNoForeground) {
  const ImageStats s = image_stats(uniform(40, 30, colours::white));
  EXPECT_EQ(s.width, 40);
  EXPECT_EQ(s.height, 30);
  EXPECT_DOUBLE_EQ(s.variance, 0.0);
  EXPECT_DOUBLE_EQ(s.non_background_share, 0.0);
}

TEST(ImageStats, HalfBlackImage) {
  Image img = uniform(10, 10, colours::white);
  for (int i = 0; i < 50; ++i) img.pixels[static_cast<std::size_t>(i)] = colours::black;
  const ImageStats s = image_stats(img);
  EXPECT_NEAR(s.variance, 127.5 * 127.5, 1e-6); // grey levels 0 and 255 in equal shares
  EXPECT_DOUBLE_EQ(s.non_background_share, 0.5);
  EXPECT_EQ(count_colour(img, colours::black), 50U);
  EXPECT_TRUE(contains_colour(img, {3, 3, 3}, 6, 50));
  EXPECT_FALSE(contains_colour(img, {200, 0, 0}));
}

TEST(ImagePng, WriteThenReadKeepsPixelsAndOrientation) {
  Image img = uniform(7, 5, colours::white);
  img.pixels[0] = {255, 0, 0};                     // top left
  img.pixels[img.pixels.size() - 1] = {0, 0, 255}; // bottom right
  const auto path = test::output("roundtrip.png");
  write_png(img, path);
  const Image back = read_png(path);
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  EXPECT_EQ(back.at(0, 0), (Rgb{255, 0, 0}));
  EXPECT_EQ(back.at(6, 4), (Rgb{0, 0, 255}));
  EXPECT_EQ(back.at(3, 2), colours::white);
}

// Background writes give the same bytes as direct ones (truth: the direct write of the same pixels), a read of a
// queued file waits for it, and finish() reports a file that could not be written.
TEST(ImagePng, BackgroundWritesGiveTheDirectBytesAndReadsWaitForThem) {
  Image img = uniform(300, 200, colours::white);
  for (std::size_t i = 0; i < img.pixels.size(); i += 7) img.pixels[i] = {static_cast<std::uint8_t>(i % 251), 40, 200};
  const auto direct = test::output("direct.png");
  write_png(img, direct);
  std::vector<std::filesystem::path> queued;
  {
    BackgroundPngWrites writes;
    for (int k = 0; k < 6; ++k) {
      queued.push_back(test::output("queued_" + std::to_string(k) + ".png"));
      write_png(img, queued.back());
    }
    const Image back = read_png(queued.back()); // queued a moment ago: waits for it
    EXPECT_EQ(back.pixels, img.pixels);
    writes.finish();
  }
  const auto bytes = [](const std::filesystem::path& f) {
    std::ifstream in(f, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  for (const auto& f : queued) EXPECT_EQ(bytes(f), bytes(direct)) << f;

  BackgroundPngWrites failing;
  write_png(img, test::output("no_such_folder") / "x.png");
  EXPECT_THROW(failing.finish(), std::runtime_error);
}

TEST(ColourMap, DivergingBlueWhiteRed) {
  const Rgb neg = diverging_colour(-1.0);
  const Rgb zero = diverging_colour(0.0);
  const Rgb pos = diverging_colour(1.0);
  EXPECT_GT(neg.b, neg.r);
  EXPECT_GT(pos.r, pos.b);
  EXPECT_GE(std::min({zero.r, zero.g, zero.b}), 240); // near white
  EXPECT_EQ(diverging_colour(-5.0), neg);             // clamped
  // Lightness falls steadily away from zero on both sides.
  const auto grey = [](Rgb c) { return 0.299 * c.r + 0.587 * c.g + 0.114 * c.b; };
  for (double t = 0.0; t < 1.0; t += 0.125) {
    EXPECT_GT(grey(diverging_colour(t)), grey(diverging_colour(t + 0.125))) << t;
    EXPECT_GT(grey(diverging_colour(-t)), grey(diverging_colour(-t - 0.125))) << t;
  }
}

TEST(ColourMap, RangeModes) {
  EXPECT_EQ(colour_range(-7.0, 12.0, {}), (Range{-12.0, 12.0})); // default: symmetric max-abs
  ColourScale data;
  data.mode = RangeMode::data;
  EXPECT_EQ(colour_range(-7.0, 12.0, data), (Range{-7.0, 12.0}));
  EXPECT_EQ(colour_range(2.0, 9.0, data), (Range{0.0, 9.0})); // widened to contain zero
  ColourScale fixed;
  fixed.mode = RangeMode::fixed;
  fixed.fixed = {-5.0, 5.0};
  EXPECT_EQ(colour_range(-7.0, 12.0, fixed), (Range{-5.0, 5.0}));
  fixed.fixed = {3.0, 3.0};
  EXPECT_THROW(colour_range(0.0, 1.0, fixed), std::invalid_argument);
}

// An ideal machine's deviations are rounding noise (1e-9 µm): the range stops at the scale's resolution (0.01 µm by
// default) instead of magnifying the noise until every tick label reads 0.000000.
TEST(ColourMap, RangeStopsAtTheResolution) {
  EXPECT_EQ(colour_range(0.0, 0.0, {}), (Range{-0.01, 0.01}));
  EXPECT_EQ(colour_range(-3e-9, 1e-9, {}), (Range{-0.01, 0.01}));
  EXPECT_EQ(colour_range(-0.004, 0.002, {}), (Range{-0.01, 0.01}));
  EXPECT_EQ(colour_range(-0.02, 0.001, {}), (Range{-0.02, 0.02})); // above the resolution: the data decide
  ColourScale data;
  data.mode = RangeMode::data;
  EXPECT_EQ(colour_range(0.0, 0.004, data), (Range{0.0, 0.01}));    // only the side the data reach
  EXPECT_EQ(colour_range(-0.004, 0.0, data), (Range{-0.01, 0.0}));
  EXPECT_EQ(colour_range(-1e-12, 2e-12, data), (Range{-0.01, 0.01})); // rounding noise: both sides
  ColourScale mrad;
  mrad.unit = "mrad";
  mrad.resolution = 1e-4;
  EXPECT_EQ(colour_range(-3e-9, 1e-9, mrad), (Range{-1e-4, 1e-4}));
  ColourScale none;
  none.resolution = 0.0; // no floor: only an empty range falls back to ±1
  EXPECT_EQ(colour_range(-3e-9, 1e-9, none), (Range{-3e-9, 3e-9}));
  EXPECT_EQ(colour_range(0.0, 0.0, none), (Range{-1.0, 1.0}));
}

TEST(ColourMap, ZeroIsWhiteAndEndsAreTheMapEnds) {
  const Range r{-7.0, 12.0};
  EXPECT_EQ(colour_for(0.0, r), diverging_colour(0.0));
  EXPECT_EQ(colour_for(-7.0, r), diverging_colour(-1.0));
  EXPECT_EQ(colour_for(12.0, r), diverging_colour(1.0));
  EXPECT_EQ(colour_for(6.0, r), diverging_colour(0.5));
  EXPECT_EQ(colour_for(-3.5, r), diverging_colour(-0.5));
  EXPECT_EQ(colour_for(40.0, r), diverging_colour(1.0)); // outside: nearer end
}

} // namespace
} // namespace geartopo::render
