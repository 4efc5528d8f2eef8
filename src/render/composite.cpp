// Composite of several PNGs: plain pixel copies, captions rasterised with FreeType on the CPU (no OpenGL).

#include "geartopo/render/composite.hpp"
#include "detail/layout.hpp"
#include "detail/offscreen.hpp"
#include "detail/overlay.hpp"
#include "geartopo/render/image.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>

namespace geartopo::render {

namespace {

/// Blends `text` (rows bottom-up) onto `canvas` with its box centred at (cx, cy) (canvas pixels, y down).
void blend_text(Image& canvas, const detail::TextRaster& text, int cx, int cy) {
  const int x0 = cx - text.width / 2;
  const int y0 = cy - text.height / 2;
  for (int ty = 0; ty < text.height; ++ty) {
    const int y = y0 + (text.height - 1 - ty);
    if (y < 0 || y >= canvas.height) continue;
    for (int tx = 0; tx < text.width; ++tx) {
      const int x = x0 + tx;
      if (x < 0 || x >= canvas.width) continue;
      const unsigned char* s = &text.rgba[(static_cast<std::size_t>(ty) * text.width + tx) * 4];
      const double a = s[3] / 255.0;
      if (a <= 0.0) continue;
      Rgb& d = canvas.pixels[static_cast<std::size_t>(y) * canvas.width + x];
      const auto mix = [a](std::uint8_t dst, unsigned char src) {
        return static_cast<std::uint8_t>(std::lround(src * a + dst * (1.0 - a)));
      };
      d = {mix(d.r, s[0]), mix(d.g, s[1]), mix(d.b, s[2])};
    }
  }
}

} // namespace

ImageSize render_composite(const Composite& composite, const std::filesystem::path& png) {
  detail::require(!composite.panels.empty(), "composite: no panel");
  detail::require(composite.gap_px >= 0, "composite: negative gap");
  std::vector<Image> images;
  int cell_w = 0;
  int cell_h = 0;
  bool captions = false;
  for (const Panel& p : composite.panels) {
    images.push_back(read_png(p.png));
    cell_w = std::max(cell_w, images.back().width);
    cell_h = std::max(cell_h, images.back().height);
    captions = captions || !p.caption.empty();
  }
  const int n = static_cast<int>(images.size());
  const int columns = composite.columns > 0 ? std::min(composite.columns, n) : n;
  const int rows = (n + columns - 1) / columns;
  const int px = detail::font_px({cell_w, cell_h}, composite.font_px);
  const int caption_h = captions ? static_cast<int>(std::lround(1.9 * px)) : 0;
  const int title_h = composite.title.empty() ? 0 : static_cast<int>(std::lround(2.6 * px));
  const int gap = composite.gap_px;

  Image canvas;
  canvas.width = columns * cell_w + (columns + 1) * gap;
  canvas.height = title_h + rows * (cell_h + caption_h) + (rows + 1) * gap;
  canvas.pixels.assign(static_cast<std::size_t>(canvas.width) * canvas.height, colours::white);

  std::lock_guard<std::mutex> lock(detail::render_mutex()); // FreeType caches are process-wide
  if (!composite.title.empty())
    blend_text(canvas,
               detail::rasterise_text(composite.title, static_cast<int>(std::lround(1.2 * px)), colours::text, true),
               canvas.width / 2, gap + title_h / 2);
  for (int k = 0; k < n; ++k) {
    const int cx = gap + (k % columns) * (cell_w + gap);
    const int cy = title_h + gap + (k / columns) * (cell_h + caption_h + gap);
    const Image& img = images[static_cast<std::size_t>(k)];
    const int ox = cx + (cell_w - img.width) / 2;
    const int oy = cy + (cell_h - img.height) / 2;
    for (int y = 0; y < img.height; ++y)
      std::copy_n(&img.pixels[static_cast<std::size_t>(y) * img.width], img.width,
                  &canvas.pixels[static_cast<std::size_t>(oy + y) * canvas.width + ox]);
    const std::string& caption = composite.panels[static_cast<std::size_t>(k)].caption;
    if (!caption.empty())
      blend_text(canvas, detail::rasterise_text(caption, px, colours::text, false), cx + cell_w / 2,
                 cy + cell_h + caption_h / 2);
  }
  write_png(canvas, png);
  return {canvas.width, canvas.height};
}

} // namespace geartopo::render
