#pragma once
// Internal: 2D text and colour-bar drawing shared by charts and 3D views (pixel coordinates, origin bottom left).
// Forward declarations only: VTK headers stay in the .cpp files.

#include "geartopo/render/common.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

class vtkContext2D;
class vtkContextItem;
class vtkTextProperty;

namespace geartopo::render::detail {

enum class VAlign { bottom, centre, top };

/// Text anchored at (x, y). h and v place the text's box (after rotation) relative to the anchor.
struct OverlayText {
  float x = 0.0F;
  float y = 0.0F;
  std::string text;
  int px = 12;
  Rgb colour = colours::text;
  bool bold = false;
  HAlign h = HAlign::left;
  VAlign v = VAlign::bottom;
  float angle_deg = 0.0F;
  bool box = false;  ///< white, slightly translucent box behind the text
  bool halo = false; ///< white outline round the glyphs (readable over lines without hiding them)
};

/// A vertical colour bar: the bar occupies (x, y, w, h); tick labels to its right, `label` rotated beside them.
struct ColourBar {
  Range range;
  std::string label;
  int px = 12;
  float x = 0.0F;
  float y = 0.0F;
  float w = 0.0F;
  float h = 0.0F;
};

struct Overlay {
  std::vector<OverlayText> texts;
  std::optional<ColourBar> bar;
};

/// Width (px) to keep free at the right edge of the image for a colour bar of `range` labelled `label`.
float colour_bar_reserve(Range range, const std::string& label, int px);
/// The colour bar placed in the reserved strip at the right of an image of `size`, vertically centred between
/// `bottom` and `top` (px from the bottom edge).
ColourBar place_colour_bar(Range range, const std::string& label, int px, ImageSize size, float bottom, float top);

/// A new context item drawing `overlay` (reference count 1: wrap with vtkSmartPointer<>::Take).
vtkContextItem* new_overlay_item(Overlay overlay);

void style_text(vtkTextProperty* property, int px, Rgb colour, bool bold);

/// Text rendered on the CPU (FreeType): RGBA, rows bottom-up, with a 1 px transparent border. Empty on failure.
struct TextRaster {
  int width = 0;
  int height = 0;
  std::vector<unsigned char> rgba;
};
TextRaster rasterise_text(const std::string& text, int px, Rgb colour, bool bold, float angle_deg = 0.0F);
/// Width and height (px) of unrotated text.
std::pair<int, int> text_size(const std::string& text, int px, bool bold = false);

void draw_text(vtkContext2D* painter, const OverlayText& text);
void draw_colour_bar(vtkContext2D* painter, const ColourBar& bar);

} // namespace geartopo::render::detail
