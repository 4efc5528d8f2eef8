// geartopo — the involute function and its inverse. Angles in rad.
#pragma once

#include <cmath>

namespace geartopo::gears {

/// inv α = tan α − α.
inline double involute(double alpha) { return std::tan(alpha) - alpha; }

/// α with inv α = value, for value ≥ 0 (Newton on tan α − α; converges from α₀ = (3·value)^(1/3)).
double inverse_involute(double value);

} // namespace geartopo::gears
