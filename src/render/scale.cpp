// Axis ranges covering what a chart must show, in whole 1-2-5 steps.

#include "geartopo/render/scale.hpp"
#include "detail/layout.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace geartopo::render {

namespace {

/// 1, 2 or 5 × 10^k, the smallest of them ≥ raw.
double step_at_least(double raw) {
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * magnitude >= raw * (1.0 - 1e-12)) return m * magnitude;
  return 10.0 * magnitude;
}

} // namespace

AxisScale covering_scale(const double* values, std::size_t count, double min_span, int target_ticks) {
  if (!(min_span >= 0.0) || !std::isfinite(min_span)) throw std::invalid_argument("covering_scale: min_span must be >= 0");
  if (target_ticks < 2) throw std::invalid_argument("covering_scale: target_ticks must be >= 2");
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (std::size_t i = 0; i < count; ++i)
    if (std::isfinite(values[i])) lo = std::min(lo, values[i]), hi = std::max(hi, values[i]);
  if (lo > hi) lo = hi = 0.0;
  // Widen symmetrically to the minimum span (at least a hair, so that a constant still gets a range).
  const double need = std::max({min_span, hi - lo, 1e-9 * std::max(1.0, std::abs(hi)), 1e-6});
  const double mid = 0.5 * (lo + hi);
  lo = std::min(lo, mid - 0.5 * need);
  hi = std::max(hi, mid + 0.5 * need);
  // The coarsest 1-2-5 step giving at least target_ticks intervals, then the fewest whole steps around [lo, hi].
  double step = step_at_least((hi - lo) / target_ticks);
  for (;;) {
    const double a = std::floor(lo / step + 1e-9) * step;
    const double b = std::ceil(hi / step - 1e-9) * step;
    if ((b - a) / step <= 2.0 * target_ticks) return {{a, b}, step};
    step = step_at_least(step * 1.5); // next 1-2-5 step
  }
}

AxisScale covering_scale(std::initializer_list<double> must_show, double min_span, int target_ticks) {
  return covering_scale(must_show.begin(), must_show.size(), min_span, target_ticks);
}

std::string tick_label(double value, double step) {
  return detail::format_value(value, detail::decimals_for_step(step));
}

} // namespace geartopo::render
