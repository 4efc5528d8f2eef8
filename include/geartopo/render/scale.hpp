#pragma once
// The value range of a chart axis chosen from what it must show (docs/rendering.md, "Scales"). Plain C++: no VTK,
// so the choice is testable on its own.

#include "geartopo/render/common.hpp"

#include <initializer_list>
#include <string>

namespace geartopo::render {

/// An axis range with its tick step: min and max are whole multiples of step, step is 1, 2 or 5 × 10^k.
struct AxisScale {
  Range range;
  double step = 1.0;
};

/// The smallest range of whole 1-2-5 steps (about `target_ticks` intervals) that contains every finite value of
/// `must_show` (e.g. a trace's deviations and the edges of its tolerance box) and spans at least `min_span`
/// (so that a trace of a few tenths of a µm is not blown up to fill the chart: its scale follows its tolerance).
/// Non-finite values are ignored; with none left the range is [−min_span/2, min_span/2] (or [−1, 1]).
/// Throws std::invalid_argument for min_span < 0 or target_ticks < 2.
AxisScale covering_scale(std::initializer_list<double> must_show, double min_span = 0.0, int target_ticks = 6);
/// The same for values held in any contiguous container.
AxisScale covering_scale(const double* values, std::size_t count, double min_span = 0.0, int target_ticks = 6);

/// A tick label as the charts write it: as many decimals as `step` needs, never "-0" (e.g. for custom ticks).
std::string tick_label(double value, double step);

} // namespace geartopo::render
