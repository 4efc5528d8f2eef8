// Shared test data for test_evaluation: the default scene gear (scenes/skmc1200w-mn14-z35.yaml: m_n 14 mm, z 35,
// α_n 20°, β 30° right hand, x 0.274, b 150 mm) computed here from the ISO 21771 formulas, independently of the
// gears library, and helpers that build synthetic traces. Units: mm, µm, rad.
#pragma once

#include "geartopo/evaluation/gear_evaluation.hpp"

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace geartopo::evaluation::test {

inline constexpr double kPi = std::numbers::pi;
inline double deg(double d) { return d * kPi / 180.0; }
inline double inv(double a) { return std::tan(a) - a; }

/// Transverse geometry at a measuring diameter d_M of a helical gear (ISO 21771), enough for pitch and runout.
struct TestGear {
  int z;
  double mn, alpha_n, beta, x, b;
  double alpha_t, d, db, beta_b, st, dM, alpha_yt, psi_y, eta;

  TestGear(int z_, double mn_, double alpha_n_deg, double beta_deg, double x_, double b_, double dM_factor = 1.0)
      : z(z_), mn(mn_), alpha_n(deg(alpha_n_deg)), beta(deg(beta_deg)), x(x_), b(b_) {
    alpha_t = std::atan(std::tan(alpha_n) / std::cos(beta));
    d = z * mn / std::cos(beta);
    db = d * std::cos(alpha_t);
    beta_b = std::asin(std::sin(beta) * std::cos(alpha_n));
    st = mn * (kPi / 2 + 2 * x * std::tan(alpha_n)) / std::cos(beta);
    dM = d * dM_factor;
    alpha_yt = std::acos(db / dM);
    psi_y = st / d + inv(alpha_t) - inv(alpha_yt); // half angular tooth thickness at d_M
    eta = kPi / z - psi_y;                         // half angular space width at d_M
  }
  PitchGeometry pitch_geometry() const { return {beta_b, alpha_yt, eta}; }
  GearParameters parameters() const { return {z, d, mn, b, beta}; }
};

/// The default scene gear.
inline TestGear scene_gear() { return TestGear(35, 14.0, 20.0, 30.0, 0.274, 150.0); }

/// Trace of f over [start, end] sampled at n equally spaced points (the ends are points), extended by `extra`
/// points of the same spacing beyond each end.
inline Trace sampled(const std::function<double(double)>& f, double start, double end, int n, int extra = 0) {
  Trace t;
  t.range_start_mm = start;
  t.range_end_mm = end;
  const double L = end - start;
  for (int i = -extra; i < n + extra; ++i) {
    const double x = i == n - 1 ? end : start + L * i / (n - 1);
    t.position_mm.push_back(x);
    t.deviation_um.push_back(f(x));
  }
  return t;
}

/// A flat trace (all zero) over [start, end] with n points.
inline Trace flat(double start, double end, int n = 21) {
  return sampled([](double) { return 0.0; }, start, end, n);
}

// Evaluation ranges of the scene gear (as gears/evaluation_ranges.cpp would give them, rounded): profile roll length
// L_α and helix axial positions L_β = [min(0.05 b, m_n), b − min(0.05 b, m_n)] = [7.5, 142.5] mm.
inline constexpr double kProfileStart = 72.0, kProfileEnd = 148.0;
inline constexpr double kHelixStart = 7.5, kHelixEnd = 142.5;

} // namespace geartopo::evaluation::test
