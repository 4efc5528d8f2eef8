// geartopo tests — synthetic residual fields with known answers for the residual analysis (docs/residual-patterns.md):
// the evaluation ranges of a large helical gear flank, reproducible Gaussian noise, grids of residuals and the options.
// Units: ξ, z, wavelengths mm; residuals, patterns, σ µm; angles rad.
//
// Noise is Gaussian from std::mt19937_64 + Box–Muller written out here (std::normal_distribution is implementation-
// defined), so every seeded case gives the same numbers on every standard library.
#pragma once

#include "geartopo/diagnosis/residuals/failing_regions.hpp"
#include "geartopo/diagnosis/residuals/flank_patterns.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>
#include <string>

namespace geartopo::diagnosis::test {

inline constexpr double kPi = std::numbers::pi;
// Evaluation ranges of a large helical gear flank (the default scene gear has m_n 14, b 150): L_α 30 mm, L_β 135 mm.
inline constexpr double kXi0 = 95.0, kXi1 = 125.0, kZ0 = 7.5, kZ1 = 142.5;
inline constexpr double kLa = kXi1 - kXi0, kLb = kZ1 - kZ0;

/// Reproducible standard normal deviates.
class Gauss {
public:
  explicit Gauss(std::uint64_t seed) : g_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = 0.0;
    do u1 = uniform(); while (u1 <= 0.0);
    const double u2 = uniform(), r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * kPi * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * kPi * u2);
  }
  double uniform() { return static_cast<double>(g_() >> 11) * 0x1.0p-53; }

private:
  std::mt19937_64 g_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

/// A residual field given as a function of (u, w), the normalised coordinates in [−1, 1].
using Field = std::function<double(double u, double w)>;

inline double u_of(double xi) { return 2.0 * (xi - kXi0) / kLa - 1.0; }
inline double w_of(double z) { return 2.0 * (z - kZ0) / kLb - 1.0; }

/// nxi roll lengths × nz axial positions spanning L_α × L_β exactly (rows root → tip, columns from the datum face),
/// residual = field + σ·N(0, 1) (σ = 0: no noise).
inline FlankResiduals grid(int nxi, int nz, const Field& field, double sigma = 0.0, std::uint64_t seed = 1, int tooth = 1,
                    Flank side = Flank::Right) {
  FlankResiduals f{tooth, side, {}, kXi0, kXi1, kZ0, kZ1};
  Gauss noise(seed);
  for (int i = 0; i < nxi; ++i)
    for (int k = 0; k < nz; ++k) {
      const double xi = kXi0 + kLa * i / (nxi - 1), z = kZ0 + kLb * k / (nz - 1);
      const double r = field(u_of(xi), w_of(z)) + (sigma > 0 ? sigma * noise() : 0.0);
      f.points.push_back({xi, z, r});
    }
  return f;
}

inline PatternOptions with_noise(double sigma) {
  PatternOptions o;
  o.noise_um = sigma;
  return o;
}

/// The two layouts every pattern and region is tested on: the 7 × 9 measuring grid and a dense 20 × 40 grid.
struct GridSize {
  int nxi, nz;
};
inline constexpr GridSize kGrids[] = {{7, 9}, {20, 40}};

inline RegionOptions region_options(double sigma, double k = 3.0) {
  RegionOptions o;
  o.noise_um = sigma;
  o.k = k;
  return o;
}

inline bool contains(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }

} // namespace geartopo::diagnosis::test
