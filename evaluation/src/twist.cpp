#include "geartopo/evaluation/twist.hpp"

#include <algorithm>
#include <stdexcept>

namespace geartopo::evaluation {
namespace {

/// The least-squares line's rise over the span of x (µm): the slope deviation of one grid line.
double rise_over_range(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0.0, my = 0.0;
  for (size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= static_cast<double>(x.size());
  my /= static_cast<double>(y.size());
  double sxy = 0.0, sxx = 0.0;
  for (size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  return sxx > 0.0 ? sxy / sxx * (*hi - *lo) : 0.0;
}

} // namespace

FlankTwist flank_twist(const std::vector<TwistGridPoint>& grid) {
  int rows = 0, cols = 0;
  for (const auto& p : grid) rows = std::max(rows, p.row), cols = std::max(cols, p.col);
  if (rows < 2 || cols < 2) throw std::invalid_argument("flank twist: a grid of at least 2 × 2 points is needed");
  const auto line = [&](bool column, int index) {
    std::vector<double> x, y;
    for (const auto& p : grid)
      if ((column ? p.col : p.row) == index) x.push_back(column ? p.roll_length_mm : p.z_mm), y.push_back(p.value_um);
    return rise_over_range(x, y);
  };
  return {line(true, cols) - line(true, 1), line(false, rows) - line(false, 1)};
}

} // namespace geartopo::evaluation
