#pragma once
// Types shared by every figure of geartopo_render (docs/rendering.md). Plain C++: no VTK here.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace geartopo::render {

/// An 8-bit sRGB colour.
struct Rgb {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

namespace colours {
inline constexpr Rgb black{0, 0, 0};
inline constexpr Rgb white{255, 255, 255};
inline constexpr Rgb text{25, 25, 25};          ///< text, axes and frames
inline constexpr Rgb grey{110, 110, 110};       ///< reference lines
inline constexpr Rgb light_grey{200, 200, 200}; ///< whole-gear surfaces, no-data cells
inline constexpr Rgb nominal{0, 0, 0};          ///< nominal grid of the topology view
inline constexpr Rgb actual{20, 70, 200};       ///< actual (deviated) grid of the topology view
inline constexpr Rgb tolerance{120, 170, 120};  ///< tolerance bands
} // namespace colours

/// Distinct colours for series 0, 1, 2 … (Tableau 10, cycling).
Rgb series_colour(std::size_t index);

/// Output size in pixels.
struct ImageSize {
  int width = 1200;
  int height = 800;
};

/// A closed interval [min, max].
struct Range {
  double min = 0.0;
  double max = 0.0;
  friend bool operator==(const Range&, const Range&) = default;
};

/// One axis of a chart: label "title [unit]" and an optional fixed range (either end may be fixed).
struct AxisSpec {
  std::string title;
  std::string unit;
  std::optional<double> min;
  std::optional<double> max;
};

enum class HAlign { left, centre, right };
enum class Corner { top_left, top_right, bottom_left, bottom_right };

/// How the colour range of a colour-mapped figure is chosen (docs/rendering.md, "Colour map").
enum class RangeMode {
  symmetric, ///< [−m, m], m = max |value| (default: equal deviations look equally strong on both sides)
  data,      ///< [min(data, 0), max(data, 0)]: the data range, widened to contain 0
  fixed,     ///< ColourScale::fixed as given (e.g. the same scale for a before/after pair)
};

/// Colour scale of a colour-mapped figure; the bar is labelled "title [unit]".
struct ColourScale {
  RangeMode mode = RangeMode::symmetric;
  Range fixed{};
  std::string title = "deviation";
  std::string unit = "µm";
  /// Smallest half-width of a `symmetric` or `data` range, in `unit` (default 0.01 µm: below what a gear measuring
  /// machine resolves). Values all smaller than this are drawn near white on a ±resolution bar, not magnified until
  /// rounding noise fills the colour range and the bar reads "0.000000" at every tick (an ideal machine's 1e-9 µm).
  double resolution = 0.01;
};

/// What a render call used: the colour range (colour-mapped figures) and the axis ranges (charts).
struct RenderResult {
  std::optional<Range> colour_range;
  std::optional<Range> x_range;
  std::optional<Range> y_range;
};

} // namespace geartopo::render
