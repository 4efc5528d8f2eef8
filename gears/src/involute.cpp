#include "geartopo/gears/involute.hpp"

#include <stdexcept>

namespace geartopo::gears {

double inverse_involute(double value) {
  if (!(value >= 0.0) || !std::isfinite(value)) throw std::domain_error("inverse_involute: value must be finite and >= 0");
  if (value == 0.0) return 0.0;
  // inv α ≈ α³/3 for small α: a start that keeps Newton on the convex branch below π/2.
  double alpha = std::cbrt(3.0 * value);
  if (alpha > 1.4) alpha = 1.4;
  for (int i = 0; i < 60; ++i) {
    const double t = std::tan(alpha);
    const double f = t - alpha - value;
    const double df = t * t; // d(tan α − α)/dα = tan² α
    const double step = f / df;
    alpha -= step;
    if (alpha <= 0.0) alpha = 1e-9;
    if (std::abs(step) < 1e-15) break;
  }
  return alpha;
}

} // namespace geartopo::gears
