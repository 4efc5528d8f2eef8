// The seeded generator (core/random.hpp) against published truth: SplitMix64's reference outputs, and the moments a
// standard normal deviate has by definition.
#include "geartopo/core/random.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

using geartopo::random::SplitMix64;

// Rosetta Code, "Pseudo-random numbers/Splitmix64": the first five outputs of seed 1234567 (the reference C code,
// S. Vigna's splitmix64.c), and Vigna's first output of seed 0 (0xE220A8397B1DCDAF).
TEST(SplitMix64, GivesThePublishedReferenceOutputs) {
  SplitMix64 g(1234567);
  const std::vector<std::uint64_t> expected{6457827717110365317ull, 3203168211198807973ull, 9817491932198370423ull,
                                            4593380528125082431ull, 16408922859458223821ull};
  for (const auto e : expected) EXPECT_EQ(g.next(), e);
  EXPECT_EQ(SplitMix64(0).next(), 0xE220A8397B1DCDAFull);
}

TEST(SplitMix64, UniformIsTheTop53BitsPlusAHalf) {
  SplitMix64 a(1234567);
  const double u = a.uniform();
  EXPECT_EQ(u, (static_cast<double>(6457827717110365317ull >> 11) + 0.5) / 9007199254740992.0);
  for (int i = 0; i < 100000; ++i) {
    const double v = a.uniform();
    ASSERT_GT(v, 0.0);
    ASSERT_LT(v, 1.0);
  }
}

// N = 10⁶ deviates: mean, variance, skewness and excess kurtosis of N(0, 1) are 0, 1, 0, 0; their standard errors are
// √(1/N), √(2/N), √(6/N), √(24/N). Each is required within 5 standard errors (a chance failure about 6e-7).
TEST(SplitMix64, NormalDeviatesHaveTheMomentsOfAStandardNormal) {
  SplitMix64 g(20261125);
  const int n = 1'000'000;
  double s1 = 0, s2 = 0, s3 = 0, s4 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = g.normal();
    s1 += x, s2 += x * x, s3 += x * x * x, s4 += x * x * x * x;
  }
  const double mean = s1 / n, m2 = s2 / n - mean * mean;
  const double skew = (s3 / n - 3 * mean * s2 / n + 2 * mean * mean * mean) / std::pow(m2, 1.5);
  const double kurt = (s4 / n - 4 * mean * s3 / n + 6 * mean * mean * s2 / n - 3 * std::pow(mean, 4)) / (m2 * m2) - 3.0;
  const double N = n;
  EXPECT_NEAR(mean, 0.0, 5 * std::sqrt(1 / N));
  EXPECT_NEAR(m2, 1.0, 5 * std::sqrt(2 / N));
  EXPECT_NEAR(skew, 0.0, 5 * std::sqrt(6 / N));
  EXPECT_NEAR(kurt, 0.0, 5 * std::sqrt(24 / N));
  // The tail: P(|x| > 3) = 0.0026998; binomial standard error √(p(1 − p)/N).
  SplitMix64 h(7);
  int beyond = 0;
  for (int i = 0; i < n; ++i) beyond += std::abs(h.normal()) > 3.0;
  EXPECT_NEAR(beyond / N, 0.0026998, 5 * std::sqrt(0.0027 / N));
}
