// geartopo — value ± uncertainty rounded per GUM §7.2.6 (uncertain_value.hpp). Unit-free.
#include "geartopo/core/uncertain_value.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace geartopo::text {

std::string with_uncertainty(double value, double u, bool explicit_plus) {
  if (!(u > 0.0) || !std::isfinite(u) || !std::isfinite(value))
    return explicit_plus ? fmt::format("{:+.4g} ± {:.2g}", value, u) : fmt::format("{:.4g} ± {:.2g}", value, u);
  // u's second significant digit sits at 10^place; rounding can carry into a new leading digit (9.97 → 10).
  int place = static_cast<int>(std::floor(std::log10(u))) - 1;
  if (std::round(u / std::pow(10.0, place)) >= 100.0) ++place;
  const double step = std::pow(10.0, place);
  const double u_rounded = std::round(u / step) * step;
  double v_rounded = std::round(value / step) * step;
  if (v_rounded == 0.0) v_rounded = 0.0; // no "-0"
  const int decimals = std::max(0, -place);
  return explicit_plus ? fmt::format("{:+.{}f} ± {:.{}f}", v_rounded, decimals, u_rounded, decimals)
                       : fmt::format("{:.{}f} ± {:.{}f}", v_rounded, decimals, u_rounded, decimals);
}

} // namespace geartopo::text
