// geartopo — quantiles and tails of the distributions behind the significance tests (χ², F, normal). Thin wrappers
// over Boost.Math (which stays inside src/core/statistics.cpp), so that no library carries its own series.
//
// Every function is unit-free and throws std::invalid_argument naming the reason when a probability is not in (0, 1)
// or a number of degrees of freedom is not finite and > 0.
#pragma once

namespace geartopo {

/// x with P(χ²_ν > x) = upper_tail, i.e. the (1 − upper_tail) quantile of the χ² distribution with ν degrees of
/// freedom (ν > 0, need not be an integer). Example: upper_tail 0.05, ν 1 → 3.841.
double chi_squared_upper_quantile(double upper_tail, double degrees_of_freedom);

/// f with P(F(ν1, ν2) > f) = upper_tail: the (1 − upper_tail) quantile of Fisher's F distribution with ν1
/// (numerator) and ν2 (denominator) degrees of freedom. Example: upper_tail 0.05, ν1 3, ν2 20 → 3.098.
double fisher_f_upper_quantile(double upper_tail, double numerator_dof, double denominator_dof);

/// x with P(N(0, 1) ≤ x) = probability: the standard normal quantile. Example: 0.99865 → 3.000.
double standard_normal_quantile(double probability);

/// P(|N(0, 1)| > k) = erfc(k/√2) for k ≥ 0: the two-sided tail beyond k standard deviations (0.27 % at k = 3).
/// Throws for k < 0 or not finite.
double standard_normal_two_sided_tail(double k);

} // namespace geartopo
