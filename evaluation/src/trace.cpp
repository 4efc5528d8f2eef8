// geartopo evaluation — profile and helix deviations of one trace. Units: mm (positions), µm (deviations).
#include "geartopo/evaluation/trace.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace geartopo::evaluation {

namespace {

[[noreturn]] void refuse(const std::string& why) { throw std::invalid_argument("trace refused: " + why); }

void validate(const Trace& t) {
  const auto& x = t.position_mm;
  const auto& y = t.deviation_um;
  if (x.size() != y.size())
    refuse(fmt::format("{} positions but {} deviations", x.size(), y.size()));
  if (!std::isfinite(t.range_start_mm) || !std::isfinite(t.range_end_mm))
    refuse("the evaluation range is not finite");
  if (!(t.range_start_mm < t.range_end_mm))
    refuse(fmt::format("empty evaluation range [{}, {}] mm (start must be below end)", t.range_start_mm,
                       t.range_end_mm));
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]))
      refuse(fmt::format("point {} is not finite (position {} mm, deviation {} µm)", i, x[i], y[i]));
    if (i > 0 && !(x[i] > x[i - 1]))
      refuse(fmt::format("positions must be strictly increasing: point {} at {} mm follows {} mm", i, x[i], x[i - 1]));
  }
  const std::size_t inside = static_cast<std::size_t>(std::count_if(
      x.begin(), x.end(), [&](double v) { return v >= t.range_start_mm && v <= t.range_end_mm; }));
  if (inside < 3)
    refuse(fmt::format("{} point(s) inside the evaluation range [{}, {}] mm; at least 3 are needed", inside,
                       t.range_start_mm, t.range_end_mm));
  // A trace that misses a range end by less than a micrometre covers it for any practical purpose (files round
  // positions; probes start a hair inside): the end value is held over that gap.
  const double slack = std::max(1e-9 * (t.range_end_mm - t.range_start_mm), kRangeSlackMm);
  if (x.front() > t.range_start_mm + slack)
    refuse(fmt::format("the trace starts at {} mm, after the evaluation range start {} mm", x.front(),
                       t.range_start_mm));
  if (x.back() < t.range_end_mm - slack)
    refuse(fmt::format("the trace ends at {} mm, before the evaluation range end {} mm", x.back(), t.range_end_mm));
}

/// Deviation at position v by linear interpolation; v within the points' span (or within the tolerated slack, in
/// which case the end point's value is used).
double value_at(const Trace& t, double v) {
  const auto& x = t.position_mm;
  const auto& y = t.deviation_um;
  const auto it = std::lower_bound(x.begin(), x.end(), v);
  if (it == x.begin()) return y.front();
  if (it == x.end()) return y.back();
  const std::size_t i = static_cast<std::size_t>(it - x.begin());
  if (x[i] == v) return y[i];
  const double w = (v - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + w * (y[i] - y[i - 1]);
}

} // namespace

TraceDeviations evaluate_trace(const Trace& t) {
  validate(t);
  const double s = t.range_start_mm, e = t.range_end_mm, L = e - s, mid = 0.5 * (s + e);

  // Vertices of the polyline cut to [s, e]; positions stored relative to the middle of the range (conditioning).
  std::vector<double> u, y;
  u.reserve(t.position_mm.size() + 2);
  y.reserve(t.position_mm.size() + 2);
  u.push_back(s - mid);
  y.push_back(value_at(t, s));
  std::size_t inside = 0;
  for (std::size_t i = 0; i < t.position_mm.size(); ++i) {
    const double v = t.position_mm[i];
    if (v >= s && v <= e) ++inside;
    if (v > s && v < e) {
      u.push_back(v - mid);
      y.push_back(t.deviation_um[i]);
    }
  }
  u.push_back(e - mid);
  y.push_back(value_at(t, e));

  // Least-squares line a + b·u of the polyline over [s, e]: a = ∫y/L, b = ∫u·y / ∫u² with ∫u² = L³/12.
  // On a segment where u and y are both linear, ∫u·y = Δ/6 · (u0 (2 y0 + y1) + u1 (y0 + 2 y1)) exactly.
  double int_y = 0.0, int_uy = 0.0;
  for (std::size_t i = 1; i < u.size(); ++i) {
    const double d = u[i] - u[i - 1];
    int_y += 0.5 * d * (y[i - 1] + y[i]);
    int_uy += d / 6.0 * (u[i - 1] * (2.0 * y[i - 1] + y[i]) + u[i] * (y[i - 1] + 2.0 * y[i]));
  }
  const double a = int_y / L;
  const double b = int_uy / (L * L * L / 12.0);

  double ymin = y[0], ymax = y[0], rmin = y[0] - (a + b * u[0]), rmax = rmin;
  for (std::size_t i = 1; i < u.size(); ++i) {
    ymin = std::min(ymin, y[i]);
    ymax = std::max(ymax, y[i]);
    const double r = y[i] - (a + b * u[i]);
    rmin = std::min(rmin, r);
    rmax = std::max(rmax, r);
  }

  TraceDeviations out;
  out.total_um = ymax - ymin;
  out.form_um = rmax - rmin;
  out.slope_um = b * L; // rise towards increasing position (tip / away from the datum face)
  out.mean_line_mid_um = a;
  out.mean_line_slope_um_per_mm = b;
  out.range_length_mm = L;
  out.points_in_range = inside;
  return out;
}

} // namespace geartopo::evaluation
