// geartopo — cubic spline construction (second-derivative "moment" form) and evaluation. Units: caller's.
#include "geartopo/core/cubic_spline.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace geartopo {

namespace {

/// Thomas algorithm for a tridiagonal system (a: sub-, b: main, c: super-diagonal). Our systems are
/// strictly diagonally dominant, so no pivoting is needed.
std::vector<double> solve_tridiagonal(std::vector<double> a, std::vector<double> b, std::vector<double> c,
                                      std::vector<double> r) {
  const std::size_t n = b.size();
  for (std::size_t i = 1; i < n; ++i) {
    const double w = a[i] / b[i - 1];
    b[i] -= w * c[i - 1];
    r[i] -= w * r[i - 1];
  }
  std::vector<double> x(n);
  x[n - 1] = r[n - 1] / b[n - 1];
  for (std::size_t i = n - 1; i-- > 0;) x[i] = (r[i] - c[i] * x[i + 1]) / b[i];
  return x;
}

} // namespace

CubicSpline::CubicSpline(std::vector<double> x, std::vector<double> y, Ends ends)
    : x_(std::move(x)), y_(std::move(y)), periodic_(ends == Ends::Periodic) {
  const std::size_t n = x_.size();
  if (n < 2 || y_.size() != n) throw std::invalid_argument("CubicSpline: need ≥ 2 knots and as many values");
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(x_[i]) || !std::isfinite(y_[i])) throw std::invalid_argument("CubicSpline: non-finite knot");
    if (i > 0 && !(x_[i] > x_[i - 1])) throw std::invalid_argument("CubicSpline: knots not strictly increasing");
  }
  if (periodic_ && y_.back() != y_.front())
    throw std::invalid_argument("CubicSpline: periodic values must close (y.back() == y.front())");

  // Evenly spaced knots (the shipped tables: every 50 mm, 25 mm, 5°, 10°): locate() computes the interval. The
  // tolerance only decides whether the computed guess is worth trying; interval() checks it against the knots.
  const double step = (x_.back() - x_.front()) / static_cast<double>(n - 1);
  bool even = true;
  for (std::size_t i = 0; i < n && even; ++i)
    even = std::abs(x_[i] - (x_.front() + static_cast<double>(i) * step)) <= 1e-9 * step;
  if (even) {
    inverse_step_ = 1.0 / step;
  } else {
    // Bucket b covers [x_0 + b·w, x_0 + (b + 1)·w), w = (x_{n−1} − x_0)/(n − 1); its start is the interval of its left
    // end. interval() corrects a bucket index that rounding put one off, so the table needs no exact edges.
    inverse_bucket_ = 1.0 / step;
    bucket_start_.resize(n - 1);
    std::size_t i = 0;
    for (std::size_t b = 0; b + 1 < n; ++b) {
      const double left = x_.front() + static_cast<double>(b) * step;
      while (i + 2 < n && x_[i + 1] <= left) ++i;
      bucket_start_[b] = static_cast<unsigned>(i);
    }
  }

  std::vector<double> h(n - 1), s(n - 1); // interval lengths and slopes
  for (std::size_t i = 0; i + 1 < n; ++i) {
    h[i] = x_[i + 1] - x_[i];
    s[i] = (y_[i + 1] - y_[i]) / h[i];
  }
  m_.assign(n, 0.0);

  if (!periodic_) {
    if (n == 2) { // straight line
      set_bounds();
      return;
    }
    if (n == 3) {       // the parabola through the three points
      const double m = 2.0 * (s[1] - s[0]) / (h[0] + h[1]);
      m_.assign(3, m);
      set_bounds();
      return;
    }
    // Unknowns M_1 … M_{n−2}; M_0 and M_{n−1} eliminated with the not-a-knot conditions
    // (third derivative continuous at x_1 and x_{n−2}).
    const std::size_t k = n - 2;
    std::vector<double> a(k, 0.0), b(k), c(k, 0.0), r(k);
    for (std::size_t j = 0; j < k; ++j) {
      const std::size_t i = j + 1;
      a[j] = h[i - 1];
      b[j] = 2.0 * (h[i - 1] + h[i]);
      c[j] = h[i];
      r[j] = 6.0 * (s[i] - s[i - 1]);
    }
    // M_0 = ((h0+h1) M_1 − h0 M_2)/h1
    b[0] += h[0] * (h[0] + h[1]) / h[1];
    c[0] -= h[0] * h[0] / h[1];
    // M_{n−1} = ((h_{n−3}+h_{n−2}) M_{n−2} − h_{n−2} M_{n−3})/h_{n−3}
    const double hl = h[n - 3], hr = h[n - 2];
    b[k - 1] += hr * (hl + hr) / hl;
    a[k - 1] -= hr * hr / hl;
    a[0] = 0.0;
    c[k - 1] = 0.0;
    const std::vector<double> mid = solve_tridiagonal(a, b, c, r);
    for (std::size_t j = 0; j < k; ++j) m_[j + 1] = mid[j];
    m_[0] = ((h[0] + h[1]) * m_[1] - h[0] * m_[2]) / h[1];
    m_[n - 1] = ((hl + hr) * m_[n - 2] - hr * m_[n - 3]) / hl;
    set_bounds();
    return;
  }

  // Periodic: unknowns M_0 … M_{m−1}, M_m ≡ M_0, cyclic indices for h and s.
  const std::size_t m = n - 1;
  if (m == 1) { // a constant
    set_bounds();
    return;
  }
  auto hc = [&](std::size_t i) { return h[(i + m) % m]; };
  auto sc = [&](std::size_t i) { return s[(i + m) % m]; };
  std::vector<double> sol;
  if (m <= 3) { // tiny: assemble densely (coincident cyclic neighbours add up)
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
    Eigen::VectorXd rhs(static_cast<Eigen::Index>(m));
    for (std::size_t i = 0; i < m; ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      A(ii, static_cast<Eigen::Index>((i + m - 1) % m)) += hc(i + m - 1);
      A(ii, ii) += 2.0 * (hc(i + m - 1) + hc(i));
      A(ii, static_cast<Eigen::Index>((i + 1) % m)) += hc(i);
      rhs(ii) = 6.0 * (sc(i) - sc(i + m - 1));
    }
    const Eigen::VectorXd v = A.partialPivLu().solve(rhs);
    sol.assign(v.data(), v.data() + v.size());
  } else { // cyclic tridiagonal, Sherman–Morrison (Numerical Recipes "cyclic")
    std::vector<double> a(m), b(m), c(m), r(m);
    for (std::size_t i = 0; i < m; ++i) {
      a[i] = hc(i + m - 1);
      b[i] = 2.0 * (hc(i + m - 1) + hc(i));
      c[i] = hc(i);
      r[i] = 6.0 * (sc(i) - sc(i + m - 1));
    }
    const double alpha = c[m - 1], beta = a[0]; // corner entries A(m−1,0) and A(0,m−1)
    const double gamma = -b[0];
    std::vector<double> bb = b;
    bb[0] -= gamma;
    bb[m - 1] -= alpha * beta / gamma;
    a[0] = 0.0;
    c[m - 1] = 0.0;
    const std::vector<double> xs = solve_tridiagonal(a, bb, c, r);
    std::vector<double> u(m, 0.0);
    u[0] = gamma;
    u[m - 1] = alpha;
    const std::vector<double> zs = solve_tridiagonal(a, bb, c, u);
    const double fact = (xs[0] + beta * xs[m - 1] / gamma) / (1.0 + zs[0] + beta * zs[m - 1] / gamma);
    sol.resize(m);
    for (std::size_t i = 0; i < m; ++i) sol[i] = xs[i] - fact * zs[i];
  }
  for (std::size_t i = 0; i < m; ++i) m_[i] = sol[i];
  m_[m] = m_[0];
  set_bounds();
}

void CubicSpline::set_bounds() noexcept {
  min_step_ = x_[1] - x_[0];
  for (std::size_t i = 1; i + 1 < x_.size(); ++i) min_step_ = std::min(min_step_, x_[i + 1] - x_[i]);
  max_abs_moment_ = 0.0;
  for (const double mi : m_) max_abs_moment_ = std::max(max_abs_moment_, std::abs(mi));
}

std::size_t CubicSpline::interval(double t) const noexcept {
  // The largest i ≤ n − 2 with x_i ≤ t (0 if none), which is what bisection (upper_bound) gives. On evenly spaced
  // knots the computed guess is off by at most one interval (rounding); on uneven ones the bucket's start is at most
  // the bucket's knots below it. The two loops move either onto that i.
  const std::size_t last = x_.size() - 2;
  if (inverse_step_ > 0.0) {
    const double guess = (t - x_.front()) * inverse_step_;
    std::size_t i = guess >= 0.0 ? static_cast<std::size_t>(std::min(guess, static_cast<double>(last))) : 0;
    while (i > 0 && t < x_[i]) --i;
    while (i < last && !(t < x_[i + 1])) ++i;
    return i;
  }
  const double bucket = (t - x_.front()) * inverse_bucket_;
  const std::size_t b = bucket >= 0.0 ? static_cast<std::size_t>(std::min(bucket, static_cast<double>(last))) : 0;
  std::size_t i = bucket_start_[b];
  while (i > 0 && t < x_[i]) --i;
  while (i < last && !(t < x_[i + 1])) ++i;
  return i;
}

CubicSpline::Location CubicSpline::locate(double t) const noexcept {
  Location l;
  if (periodic_) {
    const double p = x_.back() - x_.front();
    t = x_.front() + std::fmod(t - x_.front(), p);
    if (t < x_.front()) t += p;
    if (t >= x_.back()) t = x_.front(); // fmod rounding at the seam
  } else if (t < x_.front()) {
    l.t = t;
    l.below = true;
    return l;
  } else if (t > x_.back()) {
    l.i = x_.size() - 2;
    l.t = t;
    l.above = true;
    return l;
  }
  l.i = interval(t);
  l.t = t;
  l.h = x_[l.i + 1] - x_[l.i];
  l.a = (x_[l.i + 1] - t) / l.h;
  l.b = (t - x_[l.i]) / l.h;
  return l;
}

double CubicSpline::value_inside(const Location& l) const noexcept {
  const std::size_t i = l.i;
  const double a = l.a, b = l.b, h = l.h;
  return a * y_[i] + b * y_[i + 1] + ((a * a * a - a) * m_[i] + (b * b * b - b) * m_[i + 1]) * h * h / 6.0;
}

double CubicSpline::derivative_inside(const Location& l) const noexcept {
  const std::size_t i = l.i;
  const double a = l.a, b = l.b, h = l.h;
  return (y_[i + 1] - y_[i]) / h + (-(3.0 * a * a - 1.0) * m_[i] + (3.0 * b * b - 1.0) * m_[i + 1]) * h / 6.0;
}

double CubicSpline::value_at(const Location& l) const noexcept {
  if (l.below) return y_.front() + derivative(x_.front()) * (l.t - x_.front());
  if (l.above) return y_.back() + derivative(x_.back()) * (l.t - x_.back());
  return value_inside(l);
}

double CubicSpline::value(double t) const noexcept { return value_at(locate(t)); }

double CubicSpline::derivative(double t) const noexcept {
  Location l = locate(t);
  if (l.below) l = locate(x_.front()); // the end tangent continues outside
  if (l.above) l = locate(x_.back());
  return derivative_inside(l);
}

std::pair<double, double> CubicSpline::value_and_derivative(double t) const noexcept {
  return value_and_derivative_at(locate(t));
}

std::pair<double, double> CubicSpline::value_and_derivative_at(const Location& l) const noexcept {
  if (l.below || l.above) return {value_at(l), derivative(l.t)};
  return {value_inside(l), derivative_inside(l)};
}

double CubicSpline::second_derivative_bound(const Location& l, double reach) const noexcept {
  // τ within reach ≤ min_step_ of t ∈ [x_i, x_{i+1}] lies in [x_{i−1}, x_{i+2}], where s″ is linear between the
  // moments m_{i−1} … m_{i+2} (0 beyond the ends), so its largest |value| is at one of those knots.
  if (periodic_ || l.below || l.above || !(reach <= min_step_)) return max_abs_moment_;
  const std::size_t lo = l.i == 0 ? 0 : l.i - 1, hi = std::min(l.i + 2, m_.size() - 1);
  double bound = 0.0;
  for (std::size_t j = lo; j <= hi; ++j) bound = std::max(bound, std::abs(m_[j]));
  return bound;
}

double CubicSpline::second_derivative(double t) const noexcept {
  const Location l = locate(t);
  if (l.below || l.above) return 0.0;
  return l.a * m_[l.i] + l.b * m_[l.i + 1];
}

} // namespace geartopo
