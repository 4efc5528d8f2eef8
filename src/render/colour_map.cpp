#include "geartopo/render/colour_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace geartopo::render {

Rgb series_colour(std::size_t index) {
  static constexpr std::array<Rgb, 10> tableau{{{31, 119, 180},
                                                {214, 39, 40},
                                                {44, 160, 44},
                                                {255, 127, 14},
                                                {148, 103, 189},
                                                {140, 86, 75},
                                                {227, 119, 194},
                                                {127, 127, 127},
                                                {188, 189, 34},
                                                {23, 190, 207}}};
  return tableau[index % tableau.size()];
}

Rgb diverging_colour(double t) {
  // ColorBrewer RdBu, 9 classes, reversed (blue = negative). Designed with perceptually even lightness steps on
  // both sides of a near-white centre; its ends stay light enough for dark text on top.
  static constexpr std::array<Rgb, 9> anchors{{{33, 102, 172},
                                               {67, 147, 195},
                                               {146, 197, 222},
                                               {209, 229, 240},
                                               {247, 247, 247},
                                               {253, 219, 199},
                                               {244, 165, 130},
                                               {214, 96, 77},
                                               {178, 24, 43}}};
  if (std::isnan(t)) t = 0.0;
  const double s = (std::clamp(t, -1.0, 1.0) + 1.0) * 0.5 * (anchors.size() - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(s), anchors.size() - 2);
  const double f = s - static_cast<double>(i);
  const auto mix = [f](std::uint8_t a, std::uint8_t b) {
    return static_cast<std::uint8_t>(std::lround(a + f * (static_cast<double>(b) - a)));
  };
  const Rgb& a = anchors[i];
  const Rgb& b = anchors[i + 1];
  return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

Rgb colour_for(double value, Range range) {
  const double lo = std::min(range.min, 0.0);
  const double hi = std::max(range.max, 0.0);
  const double v = std::clamp(value, range.min, range.max);
  if (v < 0.0) return diverging_colour(lo < 0.0 ? v / -lo : 0.0);
  return diverging_colour(hi > 0.0 ? v / hi : 0.0);
}

Range colour_range(double data_min, double data_max, const ColourScale& scale) {
  if (scale.mode == RangeMode::fixed) {
    if (!(std::isfinite(scale.fixed.min) && std::isfinite(scale.fixed.max) && scale.fixed.max > scale.fixed.min))
      throw std::invalid_argument("colour scale: a fixed range needs finite min < max");
    return scale.fixed;
  }
  if (!(std::isfinite(data_min) && std::isfinite(data_max)))
    throw std::invalid_argument("colour scale: the data range is not finite");
  Range r;
  if (scale.mode == RangeMode::symmetric) {
    const double m = std::max(std::abs(data_min), std::abs(data_max));
    r = {-m, m};
  } else {
    r = {std::min(data_min, 0.0), std::max(data_max, 0.0)};
  }
  // Not below the scale's resolution: widen the side(s) the data reach, or both when the data are (near) zero.
  const double floor = scale.resolution > 0.0 ? scale.resolution : 0.0;
  if (std::max(-r.min, r.max) < floor) {
    if (scale.mode == RangeMode::symmetric || (r.min > -floor * 1e-6 && r.max < floor * 1e-6))
      r = {-floor, floor};
    else
      r = {r.min < 0.0 ? -floor : 0.0, r.max > 0.0 ? floor : 0.0};
  }
  if (r.max - r.min <= 0.0) r = {-1.0, 1.0};
  return r;
}

} // namespace geartopo::render
