// geartopo — the one random number generator behind every seeded result (Monte Carlo samples, synth's probe noise and
// stroke scatter): SplitMix64 (G. L. Steele, D. Lea, C. H. Flood, "Fast splittable pseudorandom number generators",
// OOPSLA 2014; S. Vigna's reference splitmix64.c) with normal deviates by the Box–Muller transform. Written out here
// rather than taken from <random>: std::normal_distribution is not specified bit for bit, so its output differs between
// standard libraries, and a seed would not give the same gear everywhere. The integer stream is defined bit for bit by
// the arithmetic below (tests/core/test_random.cpp pins the published reference outputs of seed 1234567); the normal
// deviates go through std::log, std::sqrt and std::cos, whose last bit may differ between maths libraries (glibc's
// are correctly rounded in practice), so a deviate agrees everywhere to about 1 ulp.
#pragma once

#include <cstdint>

namespace geartopo::random {

class SplitMix64 {
public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

  /// The next 64 random bits: state += 0x9E3779B97F4A7C15, then the reference mix (splitmix64.c).
  std::uint64_t next();
  /// Uniform in (0, 1): the top 53 bits plus one half, times 2⁻⁵³ — never 0 or 1 (Box–Muller takes a logarithm).
  double uniform();
  /// Standard normal N(0, 1) by Box–Muller: √(−2 ln u₁)·cos(2π u₂) from two uniforms, one value per call (the sine's
  /// twin is dropped, so the n-th deviate is always the n-th pair of uniforms: simple to follow, 2 words per deviate).
  double normal();

private:
  std::uint64_t state_;
};

} // namespace geartopo::random
