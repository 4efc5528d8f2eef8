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

private:
  struct Local { std::size_t i; double t; bool below, above; };
  Local locate(double t) const noexcept;
  double value_inside(const Local& l) const noexcept;      ///< l neither below nor above
  double derivative_inside(const Local& l) const noexcept; ///< l neither below nor above

  std::vector<double> x_, y_, m_; // knots, values, second derivatives at the knots
  bool periodic_ = false;
};

} // namespace geartopo
