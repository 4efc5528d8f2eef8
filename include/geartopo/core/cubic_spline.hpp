// geartopo — C² cubic interpolation of measured error tables.
//
// Not-a-knot ends for ordinary tables (reproduces any cubic exactly: no artificial zero curvature at the
// ends as with "natural" splines), periodic ends for the C axis. Units are the caller's (the error source
// stores positions in mm or rad and values in mm or rad).
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace geartopo {

class CubicSpline {
public:
  enum class Ends {
    NotAKnot, ///< 2 knots: straight line; 3 knots: the parabola; ≥ 4: not-a-knot cubic spline
    Periodic, ///< knots x_0 … x_{n−1} span exactly one period, y_{n−1} = y_0; C² across the seam
  };

  CubicSpline() = default;
  /// x strictly increasing, n ≥ 2, all finite; for Periodic also y.back() == y.front().
  /// Throws std::invalid_argument otherwise (callers check first and report file positions).
  CubicSpline(std::vector<double> x, std::vector<double> y, Ends ends);

  /// Value, first and second derivative at t. Outside [x_0, x_{n−1}] a NotAKnot spline continues as the
  /// tangent line of its end (C¹); a Periodic spline wraps t into the period. No allocation.
  double value(double t) const noexcept;
  double derivative(double t) const noexcept;
  double second_derivative(double t) const noexcept;
  /// {value(t), derivative(t)} with one search for t's interval (the same bits).
  std::pair<double, double> value_and_derivative(double t) const noexcept;

  double front() const { return x_.front(); }
  double back() const { return x_.back(); }
  bool periodic() const { return periodic_; }
  std::size_t size() const { return x_.size(); }
  /// The knots x_0 … x_{n−1} (to tell whether a table is equidistant, e.g. for a controller's compensation table).
  const std::vector<double>& knots() const { return x_; }

  /// Where t falls among the knots: the interval i with x_i ≤ t < x_{i+1} (the last interval for t = x_{n−1}; t
  /// wrapped into the period first for a Periodic spline) and, inside the table, the local coordinates of the moment
  /// form a = (x_{i+1} − t)/h, b = (t − x_i)/h, h = x_{i+1} − x_i. Found in O(1) when the knots are evenly spaced
  /// (the interval computed, then checked against the knots), from a table of equal buckets over the knots otherwise
  /// (a walk over the knots in t's bucket): the interval bisection finds either way.
  struct Location {
    std::size_t i = 0;
    double t = 0.0;
    bool below = false, above = false; ///< t < x_0 or t > x_{n−1} (never for Periodic)
    double h = 0.0, a = 0.0, b = 0.0;  ///< only when neither below nor above
  };
  Location locate(double t) const noexcept;
  /// value(t) for a location found by any spline with the same knots() (e.g. the six error components of one axis
  /// read from one table): one search for all of them, the same bits as value(t).
  double value_at(const Location& l) const noexcept;
  /// value_and_derivative(t) for t's location (locate(t)): the same bits.
  std::pair<double, double> value_and_derivative_at(const Location& l) const noexcept;
  /// An upper bound of |s″(τ)| for every τ within `reach` of l.t. s″ is linear between knots (its values there are the
  /// moments) and 0 beyond the ends of a NotAKnot spline, so when `reach` is below every knot spacing the largest
  /// |moment| of the knots x_{i−1} … x_{i+2} around l's interval bounds it; otherwise (or periodic, or t outside
  /// the knots) the largest |moment| of all. For error bounds of iterations on the spline (flank_deviation.cpp).
  double second_derivative_bound(const Location& l, double reach) const noexcept;
  /// True when the knots are evenly spaced (each within 1e-9 of an interval of where i·(x_{n−1} − x_0)/(n − 1)
  /// puts it): locate() computes the interval instead of bisecting.
  bool evenly_spaced() const { return inverse_step_ > 0.0; }

private:
  double value_inside(const Location& l) const noexcept;      ///< l neither below nor above
  double derivative_inside(const Location& l) const noexcept; ///< l neither below nor above
  std::size_t interval(double t) const noexcept;              ///< i with x_i ≤ t < x_{i+1}, t in [x_0, x_{n−1}]
  void set_bounds() noexcept;                                 ///< min_step_ and max_abs_moment_, once the moments are known

  std::vector<double> x_, y_, m_; // knots, values, second derivatives at the knots
  bool periodic_ = false;
  double inverse_step_ = 0.0; // (n − 1)/(x_{n−1} − x_0) when evenly spaced, else 0
  // Uneven knots (the wheel profile: ~2 000): n − 1 equal buckets over [x_0, x_{n−1}], each with the interval holding
  // its left end, so locate() starts there and walks the few knots inside the bucket instead of bisecting.
  double inverse_bucket_ = 0.0;
  std::vector<unsigned> bucket_start_;
  double min_step_ = 0.0;     // the smallest knot spacing
  double max_abs_moment_ = 0.0; // max |s″| over the whole spline
};

} // namespace geartopo
