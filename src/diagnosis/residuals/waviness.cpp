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

/// ΔRSS of a wave from its sums over the points (cos c_i, sin s_i of its phase): with Q the base model's orthonormal
/// basis (Qt: p × n, its transpose) and r0 the base residual (⟂ Q), the projected columns C' = C − Q QᵀC have
/// C'ᵀC' = CᵀC − (QᵀC)ᵀ(QᵀC) and C'ᵀr0 = Cᵀr0: one pass over the points, nothing allocated. Rank-deficient wave columns
/// (e.g. at the Nyquist wavelength) count with their rank.
struct WaveSums {
  double cc = 0.0, cs = 0.0, ss = 0.0, hc = 0.0, hs = 0.0;
  Eigen::VectorXd qc, qs; // QᵀC, p each
  explicit WaveSums(Eigen::Index p) : qc(Eigen::VectorXd::Zero(p)), qs(Eigen::VectorXd::Zero(p)) {}
  /// The m points at one position (count m): q the sum of their rows of Q (p), r of their residuals.
  void add(const double* q, Eigen::Index p, double m, double c, double s, double r) {
    cc += m * c * c, cs += m * c * s, ss += m * s * s, hc += c * r, hs += s * r;
    // p is 6 to 10: a plain loop over the column, not Eigen's dynamic-size expression machinery, per position.
    double* a = qc.data();
    double* b = qs.data();
    for (Eigen::Index j = 0; j < p; ++j) a[j] += c * q[j], b[j] += s * q[j];
  }
  double gain(Eigen::Index n) const {
    Eigen::Matrix2d G;
    G << cc - qc.squaredNorm(), cs - qc.dot(qs), cs - qc.dot(qs), ss - qs.squaredNorm();
    const Eigen::Vector2d h(hc, hs);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(G);
    const double top = es.eigenvalues().maxCoeff();
    if (!(top > 1e-12 * static_cast<double>(n))) return 0.0;
    double g = 0.0;
    for (int k = 0; k < 2; ++k) {
      const double lam = es.eigenvalues()(k);
      if (lam > 1e-9 * top) {
        const double proj = es.eigenvectors().col(k).dot(h);
        g += proj * proj / lam;
      }
    }
    return g;
  }
};

/// The points gathered by their position along x: a wave has one value at a position, so every sum of WaveSums over
/// the points is the sum over the positions of that value times the points' count, row sum of Q or residual sum there.
/// A trace export repeats each position on every line along it (every helix line has the same z, every profile line
/// the same ξ): ≈ 6× fewer terms per frequency than points on 3 + 3 lines.
struct Positions {
  std::vector<double> x, count, r; // per distinct position: x (mm), points there, Σ r0 (µm)
  Eigen::MatrixXd Qt;              // p × positions: Σ of the points' rows of Q
  Positions(const Eigen::MatrixXd& Qt_points, const Eigen::VectorXd& r0, const std::vector<double>& xs) {
    std::vector<std::size_t> order(xs.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return xs[a] < xs[b]; });
    std::vector<std::size_t> first; // index into `order` where each position starts
    for (std::size_t k = 0; k < order.size(); ++k)
      if (k == 0 || xs[order[k]] != xs[order[k - 1]]) first.push_back(k);
    first.push_back(order.size());
    const std::size_t g = first.size() - 1;
    Qt = Eigen::MatrixXd::Zero(Qt_points.rows(), static_cast<Eigen::Index>(g));
    x.resize(g), count.resize(g), r.assign(g, 0.0);
    for (std::size_t j = 0; j < g; ++j) {
      x[j] = xs[order[first[j]]];
      count[j] = static_cast<double>(first[j + 1] - first[j]);
      for (std::size_t k = first[j]; k < first[j + 1]; ++k) {
        const auto i = static_cast<Eigen::Index>(order[k]);
        Qt.col(static_cast<Eigen::Index>(j)) += Qt_points.col(i);
        r[j] += r0(i);
      }
    }
  }
  std::size_t size() const { return x.size(); }
};

/// RSS removed by adding a wave of frequency f (cycles/mm) along x to the base model (the positions' sums; n points).
double wave_gain(const Positions& at, Eigen::Index n, double x0, double f) {
  const Eigen::Index p = at.Qt.rows();
  WaveSums sums(p);
  for (std::size_t j = 0; j < at.size(); ++j) {
    const double ph = kTwoPi * f * (at.x[j] - x0);
    sums.add(at.Qt.data() + static_cast<Eigen::Index>(j) * p, p, at.count[j], std::cos(ph), std::sin(ph), at.r[j]);
  }
  return sums.gain(n);
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
  const Eigen::MatrixXd Qt = Q.transpose(); // p × n: a point's basis values contiguous
  const Eigen::VectorXd r0 = y - Q * (Q.transpose() * y);
  const double rss0 = r0.squaredNorm();
  const Positions at(Qt, r0, x);
  const Eigen::Index n = base.rows(), p = Qt.rows();

  // The frequency grid f_k = f_lo + k df: each position's phase advances by 2π df (x − x0) per step, so its cos and
  // sin follow by rotation instead of sincos (2000 steps drift < 1e-12; the last step, clamped to f_hi, is computed).
  const double df = 1.0 / (o.waviness_oversampling * L);
  const auto steps = static_cast<std::size_t>(std::ceil((f_hi - f_lo) / df));
  std::vector<double> cs(at.size()), sn(cs.size()), rc(cs.size()), rs(cs.size());
  for (std::size_t j = 0; j < cs.size(); ++j) {
    cs[j] = std::cos(kTwoPi * f_lo * (at.x[j] - x0)), sn[j] = std::sin(kTwoPi * f_lo * (at.x[j] - x0));
    rc[j] = std::cos(kTwoPi * df * (at.x[j] - x0)), rs[j] = std::sin(kTwoPi * df * (at.x[j] - x0));
  }
  double best_f = f_lo, best_gain = -1.0;
  for (std::size_t k = 0; k <= steps; ++k) {
    const double f = f_lo + static_cast<double>(k) * df;
    double g = 0.0;
    if (f >= f_hi) {
      g = wave_gain(at, n, x0, f_hi);
    } else {
      WaveSums sums(p);
      for (std::size_t j = 0; j < cs.size(); ++j) {
        sums.add(at.Qt.data() + static_cast<Eigen::Index>(j) * p, p, at.count[j], cs[j], sn[j], at.r[j]);
        const double cu = cs[j];
        cs[j] = cu * rc[j] - sn[j] * rs[j];
        sn[j] = sn[j] * rc[j] + cu * rs[j];
      }
      g = sums.gain(n);
    }
    if (g > best_gain) {
      best_gain = g;
      best_f = std::min(f, f_hi);
    }
  }
  // Golden-section refinement around the best grid frequency.
  double a = std::max(f_lo, best_f - df), b = std::min(f_hi, best_f + df);
  const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - gr * (b - a), e = a + gr * (b - a);
  double gc = wave_gain(at, n, x0, c), ge = wave_gain(at, n, x0, e);
  for (int it = 0; it < 60 && b - a > 1e-9 * f_hi; ++it) {
    if (gc > ge) {
      b = e;
      e = c;
      ge = gc;
      c = b - gr * (b - a);
      gc = wave_gain(at, n, x0, c);
    } else {
      a = c;
      c = e;
      gc = ge;
      e = a + gr * (b - a);
      ge = wave_gain(at, n, x0, e);
    }
  }
  const double fm = 0.5 * (a + b), gm = wave_gain(at, n, x0, fm);
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
