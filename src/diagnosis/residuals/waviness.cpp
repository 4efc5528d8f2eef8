// geartopo diagnosis — waviness scan of a flank's residual (waviness.hpp, waviness_scan.hpp,
// docs/residual-patterns.md "Waviness"). Units: mm (positions, wavelengths, frequencies in cycles/mm), µm.
#include "residuals/residual_fit.hpp"
#include "residuals/waviness_scan.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace geartopo::diagnosis {

std::string_view to_string(WaveDirection d) {
  return d == WaveDirection::Profile ? "along the profile (L_y)" : "along the face width (z)";
}

namespace residuals {
namespace {

/// RSS removed by adding a wave of frequency f (cycles/mm) along x to a base model with orthonormal basis Q, applied
/// to the base residual r0. Rank-deficient wave columns (e.g. at the Nyquist wavelength) count with their rank.
double wave_gain(const Eigen::MatrixXd& Q, const Eigen::VectorXd& r0, const std::vector<double>& x, double x0,
                 double f) {
  const Eigen::Index n = Q.rows();
  Eigen::MatrixXd C(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double ph = kTwoPi * f * (x[static_cast<std::size_t>(i)] - x0);
    C(i, 0) = std::cos(ph);
    C(i, 1) = std::sin(ph);
  }
  C -= Q * (Q.transpose() * C);
  const Eigen::Matrix2d G = C.transpose() * C;
  const Eigen::Vector2d h = C.transpose() * r0;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(G);
  const double top = es.eigenvalues().maxCoeff();
  if (!(top > 1e-12 * static_cast<double>(n))) return 0.0;
  double gain = 0.0;
  for (int k = 0; k < 2; ++k) {
    const double lam = es.eigenvalues()(k);
    if (lam > 1e-9 * top) {
      const double proj = es.eigenvectors().col(k).dot(h);
      gain += proj * proj / lam;
    }
  }
  return gain;
}

} // namespace

Eigen::MatrixXd with_wave(const Eigen::MatrixXd& A, const std::vector<double>& x, double x0, double lambda) {
  Eigen::MatrixXd B(A.rows(), A.cols() + 2);
  B.leftCols(A.cols()) = A;
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    const double ph = kTwoPi * (x[static_cast<std::size_t>(i)] - x0) / lambda;
    B(i, A.cols()) = std::cos(ph);
    B(i, A.cols() + 1) = std::sin(ph);
  }
  return B;
}

WavinessScan scan_waviness(WaveDirection dir, const Eigen::MatrixXd& base, const Eigen::VectorXd& y,
                           const std::vector<double>& x, double x0, double x1, double sigma, const PatternOptions& o) {
  WavinessScan s;
  s.direction = dir;
  const double L = x1 - x0;
  s.max_wavelength_mm = L;
  const auto d = distinct(x, 1e-6 * L);
  if (d.size() < 5 || base.rows() < base.cols() + 3) return s;
  double gap = 0.0;
  for (std::size_t i = 1; i < d.size(); ++i) gap = std::max(gap, d[i] - d[i - 1]);
  s.min_wavelength_mm = std::max(2.0 * gap, L / o.waviness_max_waves);
  if (!(s.min_wavelength_mm < L * (1.0 - 1e-9))) return s;
  s.scanned = true;

  const double f_lo = 1.0 / L, f_hi = 1.0 / s.min_wavelength_mm;
  s.independent_wavelengths = static_cast<std::size_t>(std::max(1.0, 2.0 * std::ceil(L * (f_hi - f_lo) - 1e-9)));
  s.chi2_threshold = 2.0 * std::log(static_cast<double>(s.independent_wavelengths) / o.waviness_false_alarm);

  Eigen::HouseholderQR<Eigen::MatrixXd> qr(base);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(base.rows(), base.cols());
  const Eigen::VectorXd r0 = y - Q * (Q.transpose() * y);
  const double rss0 = r0.squaredNorm();

  const double df = 1.0 / (o.waviness_oversampling * L);
  const auto steps = static_cast<std::size_t>(std::ceil((f_hi - f_lo) / df));
  double best_f = f_lo, best_gain = -1.0;
  for (std::size_t k = 0; k <= steps; ++k) {
    const double f = std::min(f_hi, f_lo + static_cast<double>(k) * df);
    const double g = wave_gain(Q, r0, x, x0, f);
    if (g > best_gain) {
      best_gain = g;
      best_f = f;
    }
  }
  // Golden-section refinement around the best grid frequency.
  double a = std::max(f_lo, best_f - df), b = std::min(f_hi, best_f + df);
  const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - gr * (b - a), e = a + gr * (b - a);
  double gc = wave_gain(Q, r0, x, x0, c), ge = wave_gain(Q, r0, x, x0, e);
  for (int it = 0; it < 60 && b - a > 1e-9 * f_hi; ++it) {
    if (gc > ge) {
      b = e;
      e = c;
      ge = gc;
      c = b - gr * (b - a);
      gc = wave_gain(Q, r0, x, x0, c);
    } else {
      a = c;
      c = e;
      gc = ge;
      e = a + gr * (b - a);
      ge = wave_gain(Q, r0, x, x0, e);
    }
  }
  const double fm = 0.5 * (a + b), gm = wave_gain(Q, r0, x, x0, fm);
  if (gm > best_gain) {
    best_gain = gm;
    best_f = fm;
  }
  s.best_wavelength_mm = 1.0 / best_f;
  s.best_chi2 = best_gain / (sigma * sigma);
  s.best_variance_drop = rss0 > 0 ? best_gain / rss0 : 0.0;
  if (s.best_chi2 > s.chi2_threshold && s.best_variance_drop >= o.waviness_min_variance_drop) {
    Waviness wv;
    wv.direction = dir;
    wv.wavelength_mm = s.best_wavelength_mm;
    wv.chi2 = s.best_chi2;
    wv.variance_drop = s.best_variance_drop;
    s.wave = wv; // amplitude and phase are filled from the final joint fit
  }
  return s;
}

} // namespace residuals
} // namespace geartopo::diagnosis
