#pragma once
// Diverging colour map for signed deviations (docs/rendering.md, "Colour map").

#include "geartopo/render/common.hpp"

namespace geartopo::render {

/// ColorBrewer RdBu (9 classes, reversed), interpolated linearly between its anchors:
/// t = −1 dark blue (33,102,172), t = 0 near-white (247,247,247), t = +1 dark red (178,24,43). t is clamped.
Rgb diverging_colour(double t);

/// Colour of `value` on the scale `range`. Zero is always near-white: negative values use the blue half scaled by
/// |min(range.min, 0)|, positive values the red half scaled by max(range.max, 0) ("two slopes" when the range is
/// not symmetric). Values outside the range take the colour of the nearer end.
Rgb colour_for(double value, Range range);

/// The colour range for data spanning [data_min, data_max] under `scale`. A zero-width result (all zeros) becomes
/// [−1, 1]. Throws std::invalid_argument for a fixed range with max <= min or non-finite data.
Range colour_range(double data_min, double data_max, const ColourScale& scale);

} // namespace geartopo::render
