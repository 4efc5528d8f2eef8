// geartopo tests — χ², F and normal quantiles against published table values (printed to 3 decimals in the usual
// tables, e.g. NIST/SEMATECH e-Handbook of Statistical Methods §1.3.6.7; so the tolerance is half a unit of the third
// decimal) and against closed forms. Unit-free.
#include "geartopo/core/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace geartopo {
namespace {

constexpr double kTableTolerance = 0.0005; // half a unit in the third decimal of a printed table

TEST(Statistics, ChiSquaredUpperQuantilesMatchTheTables) {
  EXPECT_NEAR(chi_squared_upper_quantile(0.01, 10.0), 23.209, kTableTolerance);
  EXPECT_NEAR(chi_squared_upper_quantile(0.05, 1.0), 3.841, kTableTolerance);
  EXPECT_NEAR(chi_squared_upper_quantile(0.01, 1.0), 6.635, kTableTolerance);
  EXPECT_NEAR(chi_squared_upper_quantile(0.05, 2.0), 5.991, kTableTolerance);
  EXPECT_NEAR(chi_squared_upper_quantile(0.05, 30.0), 43.773, kTableTolerance);
  EXPECT_NEAR(chi_squared_upper_quantile(0.95, 10.0), 3.940, kTableTolerance); // lower tail of the table
}

TEST(Statistics, ChiSquaredWithTwoDegreesOfFreedomIsExponential) {
  // P(χ²₂ > x) = e^(−x/2), so the upper quantile is −2 ln p exactly (down to the far tail the waviness test uses).
  for (double p : {0.5, 0.1, 1e-3, 1e-6, 1e-12})
    EXPECT_NEAR(chi_squared_upper_quantile(p, 2.0), -2.0 * std::log(p), 1e-9 * (-2.0 * std::log(p)));
}

TEST(Statistics, ChiSquaredOneAtTheThreeSigmaTailIsNine) {
  // χ²₁ = N(0, 1)², so P(χ²₁ > k²) = P(|N| > k) = erfc(k/√2): at k = 3 the quantile is 9.
  EXPECT_NEAR(chi_squared_upper_quantile(std::erfc(3.0 / std::sqrt(2.0)), 1.0), 9.0, 1e-9);
}

TEST(Statistics, FisherFUpperQuantilesMatchTheTables) {
  EXPECT_NEAR(fisher_f_upper_quantile(0.05, 3.0, 20.0), 3.098, kTableTolerance);
  EXPECT_NEAR(fisher_f_upper_quantile(0.01, 2.0, 10.0), 7.559, kTableTolerance);
  EXPECT_NEAR(fisher_f_upper_quantile(0.05, 1.0, 10.0), 4.965, kTableTolerance);
  EXPECT_NEAR(fisher_f_upper_quantile(0.05, 5.0, 5.0), 5.050, kTableTolerance);
}

TEST(Statistics, FisherFWithOneNumeratorDegreeIsTheSquaredStudentT) {
  // F(1, ν) = t_ν²: the two-sided 5 % point of t with 10 degrees of freedom is 2.228 (table), 2.228² = 4.964.
  EXPECT_NEAR(std::sqrt(fisher_f_upper_quantile(0.05, 1.0, 10.0)), 2.228, kTableTolerance);
}

TEST(Statistics, NormalQuantileAndTwoSidedTailMatchTheTables) {
  EXPECT_NEAR(standard_normal_quantile(0.99865), 3.0, kTableTolerance);
  EXPECT_NEAR(standard_normal_quantile(0.975), 1.960, kTableTolerance);
  EXPECT_NEAR(standard_normal_quantile(0.5), 0.0, 1e-12);
  EXPECT_NEAR(standard_normal_quantile(0.00135), -3.0, kTableTolerance);
  EXPECT_NEAR(standard_normal_two_sided_tail(3.0), 0.0027, 0.00005); // 0.27 % (table: 1 − 0.99730)
  EXPECT_NEAR(standard_normal_two_sided_tail(1.96), 0.050, kTableTolerance);
  EXPECT_DOUBLE_EQ(standard_normal_two_sided_tail(0.0), 1.0);
}

TEST(Statistics, RefusesProbabilitiesOutsideTheOpenUnitIntervalAndBadDegreesOfFreedom) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (double p : {0.0, 1.0, -0.1, 1.5, nan}) {
    EXPECT_THROW(chi_squared_upper_quantile(p, 3.0), std::invalid_argument) << p;
    EXPECT_THROW(fisher_f_upper_quantile(p, 3.0, 4.0), std::invalid_argument) << p;
    EXPECT_THROW(standard_normal_quantile(p), std::invalid_argument) << p;
  }
  for (double nu : {0.0, -1.0, nan, inf}) {
    EXPECT_THROW(chi_squared_upper_quantile(0.05, nu), std::invalid_argument) << nu;
    EXPECT_THROW(fisher_f_upper_quantile(0.05, nu, 4.0), std::invalid_argument) << nu;
    EXPECT_THROW(fisher_f_upper_quantile(0.05, 3.0, nu), std::invalid_argument) << nu;
  }
  EXPECT_THROW(standard_normal_two_sided_tail(-1.0), std::invalid_argument);
  EXPECT_THROW(standard_normal_two_sided_tail(nan), std::invalid_argument);
}

} // namespace
} // namespace geartopo
