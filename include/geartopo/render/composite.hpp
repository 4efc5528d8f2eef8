#pragma once
// Several rendered PNGs in one PNG (docs/rendering.md). Needs no OpenGL.

#include "geartopo/render/common.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace geartopo::render {

struct Panel {
  std::filesystem::path png;
  std::string caption; ///< written under the panel; empty → none
};

/// Panels placed row by row, `columns` per row (0 → all in one row), each centred in a cell as large as the
/// largest panel; white background.
struct Composite {
  std::string title;
  std::vector<Panel> panels;
  int columns = 0;
  int gap_px = 16;
  int font_px = 0; ///< 0 = from the panel size
};

/// Writes the composite to `png` and returns its size. Throws std::invalid_argument for no panel,
/// std::runtime_error for a panel that cannot be read or an output that cannot be written.
ImageSize render_composite(const Composite& composite, const std::filesystem::path& png);

} // namespace geartopo::render
