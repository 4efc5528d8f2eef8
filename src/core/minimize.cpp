#include "geartopo/core/minimize.hpp"

#include <cmath>
#include <stdexcept>

namespace geartopo {

// Brent (1973), "Algorithms for Minimization without Derivatives", ch. 5: parabolic steps through the three best
// points, golden-section steps whenever the parabola is not trusted; stops when the bracket is within 2·tol of x.
Minimum minimize_brent(const std::function<double(double)>& f, double a, double b, double tol) {
  if (!(a < b) || !(tol > 0.0)) throw std::invalid_argument("minimize_brent: needs a < b and tol_x > 0");
  constexpr double kGold = 0.3819660112501051;
  double x = a + kGold * (b - a), w = x, v = x;
  double fx = f(x), fw = fx, fv = fx;
  double d = 0.0, e = 0.0;
  for (int it = 0; it < 100; ++it) {
    const double m = 0.5 * (a + b);
    const double tol1 = tol + 1e-12 * std::abs(x), tol2 = 2.0 * tol1;
    if (std::abs(x - m) <= tol2 - 0.5 * (b - a)) break;
    bool golden = true;
    if (std::abs(e) > tol1) {
      double r = (x - w) * (fx - fv), q = (x - v) * (fx - fw), p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      q = std::abs(q);
      const double e_old = e;
      e = d;
      if (std::abs(p) < std::abs(0.5 * q * e_old) && p > q * (a - x) && p < q * (b - x)) {
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = (m >= x) ? tol1 : -tol1;
        golden = false;
      }
    }
    if (golden) {
      e = (x >= m) ? a - x : b - x;
      d = kGold * e;
    }
    const double u = (std::abs(d) >= tol1) ? x + d : x + (d > 0 ? tol1 : -tol1);
    const double fu = f(u);
    if (fu <= fx) {
      if (u >= x) a = x; else b = x;
      v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
    } else {
      if (u < x) a = u; else b = u;
      if (fu <= fw || w == x) {
        v = w, fv = fw, w = u, fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u, fv = fu;
      }
    }
  }
  return {x, fx};
}

} // namespace geartopo
