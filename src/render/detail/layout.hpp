#pragma once
// Internal: plain layout helpers shared by the figures (ticks, font size, labels). No VTK here.

#include "geartopo/render/common.hpp"

#include <string>
#include <vector>

namespace geartopo::render::detail {

/// Base font size in px: `requested` when > 0, else from the image size (18 px for 1200 × 800).
int font_px(ImageSize size, int requested);

/// A 1-2-5 step giving about `target` intervals over `span` (> 0).
double nice_step(double span, int target);
/// [lo, hi] padded by pad × span on both sides and rounded outwards to a nice step; a zero span is widened.
Range nice_range(double lo, double hi, double pad);
/// Multiples of nice_step(range, target) inside range (with a small tolerance).
std::vector<double> nice_ticks(Range range, int target);

/// `v` with `decimals` decimals, never "-0.0".
std::string format_value(double v, int decimals);
/// Decimals that show steps of `step` (0 for step >= 1).
int decimals_for_step(double step);
/// "title [unit]", or the title alone.
std::string axis_label(const std::string& title, const std::string& unit);

/// A TrueType font with Greek letters and µ (DejaVu Sans) when installed, else "" (VTK's built-in Arial).
const std::string& font_file(bool bold);

/// Rough width in px of `text` at `px` (for layout before any rendering): 0.64 em per character (DejaVu digits).
double text_width_estimate(const std::string& text, int px);

/// Throws std::invalid_argument(what) unless `ok`.
void require(bool ok, const std::string& what);

} // namespace geartopo::render::detail
