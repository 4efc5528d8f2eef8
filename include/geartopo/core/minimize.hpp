// geartopo — one-dimensional minimisation by Brent's method (parabolic steps safeguarded by golden sections).
//
// Why not Boost.Math's brent_find_minima (Boost is a dependency for the statistics): its tolerance is relative,
// 2^(1−bits)·(|x| + ¼) with bits capped at half the mantissa, and on the exact stroke search's depth functions
// (tests/grinding/test_exact_search.cpp, errors ten times the realistic ones) it stopped up to 1.8e-6 mm above the
// minimum that this implementation and the parabola shortcut agree on to 1e-8 mm. This one stops on an absolute
// tolerance in x, which is what the search asks for (mm).
#pragma once

#include <functional>

namespace geartopo {

struct Minimum {
  double x = 0.0;     ///< where f is smallest
  double value = 0.0; ///< f(x)
};

/// A local minimum of f on [a, b] (a < b), x to within tol (absolute, same unit as x, > 0; 1e-12·|x| is added so
/// that a tolerance below the spacing of doubles still ends). At most 101 evaluations of f.
Minimum minimize_brent(const std::function<double(double)>& f, double a, double b, double tol);

} // namespace geartopo
