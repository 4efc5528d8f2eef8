// geartopo core — χ², F and normal quantiles from Boost.Math (its quantile(complement(…)) keeps full relative
// precision in the far upper tail, where 1 − p would lose digits).
#include "geartopo/core/statistics.hpp"

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/normal.hpp>
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string_view>

namespace geartopo {
namespace {

void check_probability(std::string_view what, double p) {
  if (!(p > 0.0 && p < 1.0)) // also refuses NaN
    throw std::invalid_argument(fmt::format("{}: probability {} (must be in (0, 1))", what, p));
}

void check_dof(std::string_view what, std::string_view which, double nu) {
  if (!(std::isfinite(nu) && nu > 0.0))
    throw std::invalid_argument(fmt::format("{}: {} degrees of freedom {} (must be finite and > 0)", what, which, nu));
}

} // namespace

double chi_squared_upper_quantile(double upper_tail, double degrees_of_freedom) {
  constexpr std::string_view what = "χ² upper quantile";
  check_probability(what, upper_tail);
  check_dof(what, "the", degrees_of_freedom);
  const boost::math::chi_squared_distribution<double> chi2(degrees_of_freedom);
  return boost::math::quantile(boost::math::complement(chi2, upper_tail));
}

double fisher_f_upper_quantile(double upper_tail, double numerator_dof, double denominator_dof) {
  constexpr std::string_view what = "F upper quantile";
  check_probability(what, upper_tail);
  check_dof(what, "numerator", numerator_dof);
  check_dof(what, "denominator", denominator_dof);
  const boost::math::fisher_f_distribution<double> f(numerator_dof, denominator_dof);
  return boost::math::quantile(boost::math::complement(f, upper_tail));
}

double standard_normal_quantile(double probability) {
  check_probability("normal quantile", probability);
  return boost::math::quantile(boost::math::normal_distribution<double>(0.0, 1.0), probability);
}

double standard_normal_two_sided_tail(double k) {
  if (!(std::isfinite(k) && k >= 0.0))
    throw std::invalid_argument(fmt::format("normal two-sided tail: k = {} (must be finite and ≥ 0)", k));
  // 2 P(N > k) through the complement: no cancellation against 1 for large k.
  return 2.0 * boost::math::cdf(boost::math::complement(boost::math::normal_distribution<double>(0.0, 1.0), k));
}

} // namespace geartopo
