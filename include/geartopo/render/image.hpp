#pragma once
// PNG images as plain pixels, and the checks the tests (and anyone curious) run on rendered figures.

#include "geartopo/render/common.hpp"

#include <cstddef>
#include <filesystem>
#include <vector>

namespace geartopo::render {

/// An RGB image, rows from the top.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<Rgb> pixels; ///< width × height, row-major, top row first
  const Rgb& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// Reads an 8-bit RGB, RGBA, grey or grey+alpha PNG (alpha is dropped). Throws std::runtime_error.
Image read_png(const std::filesystem::path& png);
/// Writes an RGB PNG. Throws std::runtime_error when the file cannot be written.
void write_png(const Image& image, const std::filesystem::path& png);

/// While one is alive, every PNG this library writes (figures, panels, composites) is encoded and written on one
/// background thread, so that the next figure renders meanwhile: both cores busy. The pixels are copied first, so the
/// files are byte for byte what a direct write gives. read_png of a file still queued waits for it. finish() waits
/// for every file and rethrows the first write's error; the destructor waits and drops errors (an exception is
/// already on its way). At most one per process at a time (std::logic_error otherwise).
class BackgroundPngWrites {
public:
  BackgroundPngWrites();
  ~BackgroundPngWrites();
  BackgroundPngWrites(const BackgroundPngWrites&) = delete;
  BackgroundPngWrites& operator=(const BackgroundPngWrites&) = delete;
  void finish();
};

struct ImageStats {
  int width = 0;
  int height = 0;
  double variance = 0.0;             ///< of the grey level 0…255 over all pixels
  double non_background_share = 0.0; ///< share of pixels differing from the background by more than tolerance
};

/// Statistics of `image`; a pixel is background when every channel is within `tolerance` of `background`.
ImageStats image_stats(const Image& image, Rgb background = colours::white, int tolerance = 6);
ImageStats image_stats(const std::filesystem::path& png, Rgb background = colours::white, int tolerance = 6);

/// Number of pixels whose every channel is within `tolerance` of `colour`.
std::size_t count_colour(const Image& image, Rgb colour, int tolerance = 6);
/// True when at least `min_pixels` pixels match `colour` within `tolerance`.
bool contains_colour(const Image& image, Rgb colour, int tolerance = 6, std::size_t min_pixels = 4);

} // namespace geartopo::render
