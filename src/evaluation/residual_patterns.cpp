// geartopo evaluation — residual patterns, tooth trends, failing regions, summary statistics
// (docs/residual-patterns.md). Units: mm (ξ, z, wavelengths), µm (residuals, patterns, σ), rad.
#include "geartopo/evaluation/residual_patterns.hpp"

#include "geartopo/evaluation/trace.hpp" // kRangeSlackMm

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <stdexcept>

namespace geartopo::evaluation {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr std::size_t kLegendreTerms = 6;
/// Region tendencies: a fitted change counts when it exceeds this many standard errors and this fraction of the
/// region's mean |residual|.
constexpr double kTendencySigmas = 3.0;
constexpr double kTendencyFraction = 0.25;

[[noreturn]] void refuse(std::string_view what, const std::string& why) {
  throw std::invalid_argument(fmt::format("{} refused: {}", what, why));
}

std::string flank_name(int tooth, Flank side) { return fmt::format("tooth {}, {} flank", tooth, to_string(side)); }

// ------------------------------------------------------------------------------------------------ input preparation

/// In-range points of one flank with normalised coordinates.
struct Prepared {
  std::vector<std::size_t> index; ///< into FlankResiduals::points
  std::vector<double> xi, z, u, w, r;
  std::size_t outside = 0;
  std::size_t size() const { return index.size(); }
};

void check_range(std::string_view what, const FlankResiduals& f, double a, double b, const char* name) {
  if (!std::isfinite(a) || !std::isfinite(b))
    refuse(what, fmt::format("{}: the {} range is not finite", flank_name(f.tooth, f.side), name));
  if (!(a < b))
    refuse(what, fmt::format("{}: the {} range [{}, {}] mm has no length (start must be below end)",
                             flank_name(f.tooth, f.side), name, a, b));
}

Prepared prepare(const FlankResiduals& f, std::string_view what) {
  if (f.tooth < 1) refuse(what, fmt::format("tooth number {} (teeth are numbered from 1)", f.tooth));
  check_range(what, f, f.xi_start_mm, f.xi_end_mm, "roll length (L_α)");
  check_range(what, f, f.z_start_mm, f.z_end_mm, "axial (L_β)");
  if (f.points.empty()) refuse(what, fmt::format("{}: no points", flank_name(f.tooth, f.side)));
  Prepared p;
  const double s = kRangeSlackMm;
  for (std::size_t i = 0; i < f.points.size(); ++i) {
    const auto& q = f.points[i];
    if (!std::isfinite(q.xi_mm) || !std::isfinite(q.z_mm) || !std::isfinite(q.residual_um))
      refuse(what, fmt::format("{}: point {} is not finite (ξ {} mm, z {} mm, residual {} µm)",
                               flank_name(f.tooth, f.side), i, q.xi_mm, q.z_mm, q.residual_um));
    if (q.xi_mm < f.xi_start_mm - s || q.xi_mm > f.xi_end_mm + s || q.z_mm < f.z_start_mm - s ||
        q.z_mm > f.z_end_mm + s) {
      ++p.outside;
      continue;
    }
    p.index.push_back(i);
    p.xi.push_back(q.xi_mm);
    p.z.push_back(q.z_mm);
    p.u.push_back(2.0 * (q.xi_mm - f.xi_start_mm) / (f.xi_end_mm - f.xi_start_mm) - 1.0);
    p.w.push_back(2.0 * (q.z_mm - f.z_start_mm) / (f.z_end_mm - f.z_start_mm) - 1.0);
    p.r.push_back(q.residual_um);
  }
  if (p.index.empty())
    refuse(what, fmt::format("{}: none of its {} points lies inside the evaluation ranges ξ [{}, {}] mm, z [{}, {}] mm",
                             flank_name(f.tooth, f.side), f.points.size(), f.xi_start_mm, f.xi_end_mm, f.z_start_mm,
                             f.z_end_mm));
  return p;
}

void check_noise(std::string_view what, double sigma) {
  if (!std::isfinite(sigma) || !(sigma > 0.0))
    refuse(what, fmt::format("noise level σ = {} µm (must be finite and > 0)", sigma));
}

/// Sorted distinct values (values closer than tol merge into the first of them).
std::vector<double> distinct(std::vector<double> v, double tol) {
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (double x : v)
    if (out.empty() || x - out.back() > tol) out.push_back(x);
  return out;
}

// ------------------------------------------------------------------------------------------------ least squares

struct LsFit {
  Eigen::VectorXd coef;
  Eigen::MatrixXd cov_unit; ///< (AᵀA)⁻¹: covariance of coef per unit noise variance
  Eigen::VectorXd resid;
  double rss = 0.0;
};

/// Ordinary least squares; nullopt when A does not have full column rank.
std::optional<LsFit> least_squares(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  if (A.rows() < A.cols()) return std::nullopt;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  qr.setThreshold(1e-10);
  if (qr.rank() < A.cols()) return std::nullopt;
  LsFit f;
  f.coef = qr.solve(y);
  const Eigen::MatrixXd AtA = A.transpose() * A;
  f.cov_unit = AtA.ldlt().solve(Eigen::MatrixXd::Identity(A.cols(), A.cols()));
  f.resid = y - A * f.coef;
  f.rss = f.resid.squaredNorm();
  return f;
}

Eigen::MatrixXd legendre_design(const Prepared& p) {
  const auto n = static_cast<Eigen::Index>(p.size());
  Eigen::MatrixXd A(n, static_cast<Eigen::Index>(kLegendreTerms));
  for (Eigen::Index i = 0; i < n; ++i) {
    const double u = p.u[static_cast<std::size_t>(i)], w = p.w[static_cast<std::size_t>(i)];
    A(i, 0) = 1.0;
    A(i, 1) = u;
    A(i, 2) = w;
    A(i, 3) = u * w;
    A(i, 4) = 0.5 * (3.0 * u * u - 1.0);
    A(i, 5) = 0.5 * (3.0 * w * w - 1.0);
  }
  return A;
}

/// Appends cos and sin columns of a wave of wavelength λ along x (relative to x0).
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

/// Amplitude and phase of a cos + b sin = A cos(θ − φ), with standard errors from the 2 × 2 covariance (delta method).
void amplitude_phase(double a, double b, const Eigen::Matrix2d& cov, Estimate& amp, Estimate& phase) {
  const double A = std::hypot(a, b);
  double phi = std::atan2(b, a);
  if (phi < 0) phi += kTwoPi;
  amp.value = A;
  phase.value = phi;
  if (A > 0) {
    const Eigen::Vector2d g(a / A, b / A), h(-b / (A * A), a / (A * A));
    amp.standard_error = std::sqrt(std::max(0.0, g.dot(cov * g)));
    phase.standard_error = std::sqrt(std::max(0.0, h.dot(cov * h)));
  } else {
    amp.standard_error = std::sqrt(std::max(0.0, 0.5 * cov.trace()));
    phase.standard_error = std::numbers::pi; // undetermined
  }
}

// ------------------------------------------------------------------------------------------------ waviness scan

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

/// Scans wavelengths along x (ξ or z) for the single sinusoid that removes the most RSS from the base model.
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

std::string signed_um(double v, int decimals = 2) { return fmt::format("{:+.{}f} µm", v, decimals); }

// ------------------------------------------------------------------------------------------------ statistics helpers

/// Upper regularised incomplete gamma function Q(a, x) (Numerical Recipes: series / continued fraction).
double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  const double lg = std::lgamma(a);
  if (x < a + 1.0) {
    double sum = 1.0 / a, term = sum, ap = a;
    for (int n = 0; n < 1000; ++n) {
      ap += 1.0;
      term *= x / ap;
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-15) break;
    }
    return std::max(0.0, 1.0 - sum * std::exp(-x + a * std::log(x) - lg));
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - lg) * h;
}

/// x with P(χ²_ν > x) = p.
double chi2_upper_quantile(double p, double nu) {
  double lo = 0.0, hi = std::max(10.0, 10.0 * nu);
  while (gamma_q(0.5 * nu, 0.5 * hi) > p) hi *= 2.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (gamma_q(0.5 * nu, 0.5 * mid) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Regularised incomplete beta function I_x(a, b) (Numerical Recipes: continued fraction, modified Lentz).
double incomplete_beta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double front =
      std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
  const auto cf = [](double a_, double b_, double x_) {
    const double tiny = 1e-300;
    double c = 1.0, d = 1.0 - (a_ + b_) * x_ / (a_ + 1.0);
    if (std::abs(d) < tiny) d = tiny;
    d = 1.0 / d;
    double h = d;
    for (int m = 1; m < 1000; ++m) {
      const double m2 = 2.0 * m;
      double aa = m * (b_ - m) * x_ / ((a_ + m2 - 1.0) * (a_ + m2));
      d = 1.0 + aa * d;
      if (std::abs(d) < tiny) d = tiny;
      c = 1.0 + aa / c;
      if (std::abs(c) < tiny) c = tiny;
      d = 1.0 / d;
      h *= d * c;
      aa = -(a_ + m) * (a_ + b_ + m) * x_ / ((a_ + m2) * (a_ + m2 + 1.0));
      d = 1.0 + aa * d;
      if (std::abs(d) < tiny) d = tiny;
      c = 1.0 + aa / c;
      if (std::abs(c) < tiny) c = tiny;
      d = 1.0 / d;
      const double del = d * c;
      h *= del;
      if (std::abs(del - 1.0) < 1e-15) break;
    }
    return h;
  };
  if (x < (a + 1.0) / (a + b + 2.0)) return front * cf(a, b, x) / a;
  return 1.0 - front * cf(b, a, 1.0 - x) / b;
}

/// f with P(F(ν1, ν2) > f) = p.
double f_upper_quantile(double p, double nu1, double nu2) {
  const auto tail = [&](double f) { return incomplete_beta(0.5 * nu2, 0.5 * nu1, nu2 / (nu2 + nu1 * f)); };
  double lo = 0.0, hi = 10.0;
  while (tail(hi) > p) hi *= 2.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (tail(mid) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct WeightedFit {
  Eigen::VectorXd coef;
  Eigen::MatrixXd cov;
  double chi2 = 0.0;
};

/// Weighted least squares with weights 1/s²; nullopt when X does not have full column rank.
std::optional<WeightedFit> weighted_fit(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, const Eigen::VectorXd& s) {
  Eigen::MatrixXd Xw = X;
  Eigen::VectorXd yw = y;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    Xw.row(i) /= s(i);
    yw(i) /= s(i);
  }
  auto f = least_squares(Xw, yw);
  if (!f) return std::nullopt;
  return WeightedFit{f->coef, f->cov_unit, f->rss};
}

} // namespace

// ===================================================================================================== names

std::string_view to_string(NamedPattern p) {
  switch (p) {
  case NamedPattern::Offset: return "offset";
  case NamedPattern::ProfileSlope: return "profile slope";
  case NamedPattern::HelixSlope: return "helix slope";
  case NamedPattern::Twist: return "twist";
  case NamedPattern::ProfileCrowning: return "profile crowning";
  case NamedPattern::HelixCrowning: return "helix crowning";
  }
  return "?";
}

std::string_view to_string(WaveDirection d) {
  return d == WaveDirection::Profile ? "along the profile (ξ)" : "along the face width (z)";
}

std::string_view to_string(TrendKind k) {
  switch (k) {
  case TrendKind::Constant: return "constant";
  case TrendKind::Difference: return "difference";
  case TrendKind::Linear: return "linear";
  case TrendKind::OncePerRevolution: return "once per revolution";
  case TrendKind::Irregular: return "irregular";
  }
  return "?";
}

std::string_view to_string(ProfileZone z) {
  switch (z) {
  case ProfileZone::RootThird: return "root third";
  case ProfileZone::Middle: return "middle of the profile";
  case ProfileZone::TipThird: return "tip third";
  case ProfileZone::RootHalf: return "root half";
  case ProfileZone::TipHalf: return "tip half";
  case ProfileZone::Whole: return "whole profile";
  }
  return "?";
}

std::string_view to_string(AxialZone z) {
  switch (z) {
  case AxialZone::DatumFaceEnd: return "near the datum face";
  case AxialZone::Middle: return "mid face width";
  case AxialZone::FarFaceEnd: return "near the far face";
  case AxialZone::DatumFaceHalf: return "half towards the datum face";
  case AxialZone::FarFaceHalf: return "half towards the far face";
  case AxialZone::Whole: return "whole face width";
  }
  return "?";
}

// ===================================================================================================== 1. patterns

Estimate pattern_value(const FlankPatterns& f, NamedPattern p) {
  switch (p) {
  case NamedPattern::Offset: return f.offset_um;
  case NamedPattern::ProfileSlope: return f.profile_slope_um;
  case NamedPattern::HelixSlope: return f.helix_slope_um;
  case NamedPattern::Twist: return f.twist_um;
  case NamedPattern::ProfileCrowning: return f.profile_crowning_um;
  case NamedPattern::HelixCrowning: return f.helix_crowning_um;
  }
  return {};
}

FlankPatterns fit_flank_patterns(const FlankResiduals& flank, const PatternOptions& o) {
  constexpr std::string_view what = "residual pattern fit";
  check_noise(what, o.noise_um);
  if (!(o.waviness_false_alarm > 0.0 && o.waviness_false_alarm < 1.0))
    refuse(what, fmt::format("waviness false-alarm probability {} (must be in (0, 1))", o.waviness_false_alarm));
  if (!(o.waviness_min_variance_drop >= 0.0 && o.waviness_min_variance_drop < 1.0))
    refuse(what, fmt::format("waviness minimum variance drop {} (must be in [0, 1))", o.waviness_min_variance_drop));
  if (!(o.waviness_oversampling >= 1.0 && std::isfinite(o.waviness_oversampling)))
    refuse(what, fmt::format("waviness oversampling {} (must be ≥ 1)", o.waviness_oversampling));
  if (!(o.waviness_max_waves >= 1.0 && std::isfinite(o.waviness_max_waves)))
    refuse(what, fmt::format("waviness max waves {} (must be ≥ 1)", o.waviness_max_waves));
  const Prepared p = prepare(flank, what);
  const std::string name = flank_name(flank.tooth, flank.side);
  if (p.size() < kLegendreTerms)
    refuse(what, fmt::format("{}: {} point(s) inside the evaluation ranges, fewer than the {} pattern parameters", name,
                             p.size(), kLegendreTerms));
  const std::size_t nxi = distinct(p.xi, 1e-6 * (flank.xi_end_mm - flank.xi_start_mm)).size();
  const std::size_t nz = distinct(p.z, 1e-6 * (flank.z_end_mm - flank.z_start_mm)).size();
  if (nxi < 3 || nz < 3)
    refuse(what, fmt::format("{}: {} distinct roll length(s) and {} distinct axial position(s); at least 3 of each "
                             "are needed to separate slopes from crownings",
                             name, nxi, nz));

  const double sigma = o.noise_um;
  Eigen::VectorXd y(static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i) y(static_cast<Eigen::Index>(i)) = p.r[i];
  Eigen::MatrixXd A = legendre_design(p);
  if (!least_squares(A, y))
    refuse(what, fmt::format("{}: the points do not determine the six patterns (degenerate layout)", name));

  FlankPatterns out;
  out.tooth = flank.tooth;
  out.side = flank.side;
  out.noise_um = sigma;
  out.points_used = p.size();
  out.points_outside_range = p.outside;

  // Waviness: along z on the Legendre model, then along ξ with a significant z wave included.
  out.waviness_helix =
      scan_waviness(WaveDirection::Helix, A, y, p.z, flank.z_start_mm, flank.z_end_mm, sigma, o);
  if (out.waviness_helix.wave) {
    auto B = with_wave(A, p.z, flank.z_start_mm, out.waviness_helix.wave->wavelength_mm);
    if (least_squares(B, y)) A = std::move(B);
    else out.waviness_helix.wave.reset();
  }
  out.waviness_profile =
      scan_waviness(WaveDirection::Profile, A, y, p.xi, flank.xi_start_mm, flank.xi_end_mm, sigma, o);
  if (out.waviness_profile.wave) {
    auto B = with_wave(A, p.xi, flank.xi_start_mm, out.waviness_profile.wave->wavelength_mm);
    if (least_squares(B, y)) A = std::move(B);
    else out.waviness_profile.wave.reset();
  }

  const auto fit = least_squares(A, y);
  if (!fit) refuse(what, fmt::format("{}: the final pattern fit is degenerate", name)); // not expected
  const double var = sigma * sigma;
  for (std::size_t k = 0; k < kLegendreTerms; ++k) {
    const auto ki = static_cast<Eigen::Index>(k);
    out.legendre_um[k] = {fit->coef(ki), std::sqrt(var * fit->cov_unit(ki, ki))};
  }
  const auto scaled = [&](std::size_t k, double factor) {
    return Estimate{factor * out.legendre_um[k].value, std::abs(factor) * out.legendre_um[k].standard_error};
  };
  out.offset_um = scaled(0, 1.0);
  out.profile_slope_um = scaled(1, 2.0);
  out.helix_slope_um = scaled(2, 2.0);
  out.twist_um = scaled(3, 4.0);
  out.profile_crowning_um = scaled(4, -1.5);
  out.helix_crowning_um = scaled(5, -1.5);

  Eigen::Index col = static_cast<Eigen::Index>(kLegendreTerms);
  for (WavinessScan* s : {&out.waviness_helix, &out.waviness_profile}) {
    if (!s->wave) continue;
    const Eigen::Matrix2d cov = var * fit->cov_unit.block<2, 2>(col, col);
    amplitude_phase(fit->coef(col), fit->coef(col + 1), cov, s->wave->amplitude_um, s->wave->phase_rad);
    const double x0 = s->direction == WaveDirection::Helix ? flank.z_start_mm : flank.xi_start_mm;
    s->wave->first_crest_mm = x0 + s->wave->phase_rad.value / kTwoPi * s->wave->wavelength_mm;
    col += 2;
  }

  const double n = static_cast<double>(p.size());
  out.rms_residual_um = std::sqrt(y.squaredNorm() / n);
  out.rms_unexplained_um = std::sqrt(fit->rss / n);
  const double dof = n - static_cast<double>(A.cols());
  out.chi2_per_dof = dof > 0 ? fit->rss / (var * dof) : 0.0;
  return out;
}

std::string describe_patterns(const FlankPatterns& f) {
  std::string s = flank_name(f.tooth, f.side) + ":";
  for (NamedPattern p : kNamedPatterns) {
    const Estimate e = pattern_value(f, p);
    s += fmt::format(" {} {:+.2f} ± {:.2f} µm", to_string(p), e.value, e.standard_error);
    if (p == NamedPattern::Offset) s += e.value >= 0 ? " (thicker)" : " (thinner)";
    s += p == NamedPattern::HelixCrowning ? ";" : ",";
  }
  bool any = false;
  for (const WavinessScan* w : {&f.waviness_helix, &f.waviness_profile}) {
    if (!w->wave) continue;
    any = true;
    s += fmt::format(" waviness {}: amplitude {:.2f} ± {:.2f} µm, wavelength {:.1f} mm, first crest at {:.1f} mm;",
                     to_string(w->direction), w->wave->amplitude_um.value, w->wave->amplitude_um.standard_error,
                     w->wave->wavelength_mm, w->wave->first_crest_mm);
  }
  if (!any) s += " no significant waviness;";
  s += fmt::format(" RMS {:.2f} µm, unexplained {:.2f} µm (σ {:.2f} µm)", f.rms_residual_um, f.rms_unexplained_um,
                   f.noise_um);
  return s;
}

// ===================================================================================================== 2. trends

SideTrends fit_tooth_trends(std::span<const FlankPatterns> flanks, int teeth_in_gear, const TrendOptions& o) {
  constexpr std::string_view what = "tooth trend fit";
  if (teeth_in_gear < 2) refuse(what, fmt::format("{} teeth in the gear (at least 2)", teeth_in_gear));
  if (flanks.size() < 2) refuse(what, fmt::format("{} flank(s); trends need at least 2 teeth", flanks.size()));
  if (!(o.significance_sigmas > 0.0 && std::isfinite(o.significance_sigmas)))
    refuse(what, fmt::format("significance {} σ (must be finite and > 0)", o.significance_sigmas));
  const Flank side = flanks.front().side;
  std::vector<std::size_t> order(flanks.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  for (const auto& f : flanks) {
    if (f.side != side)
      refuse(what, fmt::format("flanks of both sides given (tooth {} is {}, tooth {} is {}); trends are per side",
                               flanks.front().tooth, to_string(side), f.tooth, to_string(f.side)));
    if (f.tooth < 1 || f.tooth > teeth_in_gear)
      refuse(what, fmt::format("tooth {} outside 1..{}", f.tooth, teeth_in_gear));
    for (NamedPattern p : kNamedPatterns) {
      const Estimate e = pattern_value(f, p);
      if (!std::isfinite(e.value) || !std::isfinite(e.standard_error) || !(e.standard_error > 0))
        refuse(what, fmt::format("tooth {}: {} = {} ± {} µm (needs a finite value and a standard error > 0)", f.tooth,
                                 to_string(p), e.value, e.standard_error));
    }
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return flanks[a].tooth < flanks[b].tooth; });
  for (std::size_t i = 1; i < order.size(); ++i)
    if (flanks[order[i]].tooth == flanks[order[i - 1]].tooth)
      refuse(what, fmt::format("tooth {} given twice", flanks[order[i]].tooth));

  SideTrends out;
  out.side = side;
  out.teeth_in_gear = teeth_in_gear;
  for (std::size_t i : order) out.teeth.push_back(flanks[i].tooth);

  const double k = o.significance_sigmas;
  const double p0 = std::erfc(k / std::numbers::sqrt2); // two-sided normal tail at k σ
  const auto n = static_cast<Eigen::Index>(order.size());
  const std::string teeth_text = fmt::format("{} {} flanks", order.size(), to_string(side));
  // Birge ratio of a model with p parameters: χ²/(n − p) when the teeth scatter more than their standard errors
  // allow (then standard errors are scaled by its root), else 1.
  const auto birge = [&](double chi2, Eigen::Index p) {
    return n > p ? std::max(1.0, chi2 / static_cast<double>(n - p)) : 1.0;
  };
  // Does adding q parameters (removing dchi of χ²) to reach a model with p parameters and χ² chi2 explain
  // significantly more? Against χ²_q when the model's scatter is consistent with the standard errors, else against
  // F(q, n − p) with the observed scatter (an F test).
  const auto significant = [&](double dchi, int q, double chi2, Eigen::Index p) {
    const double q_d = static_cast<double>(q);
    if (n > p && chi2 / static_cast<double>(n - p) > 1.0)
      return dchi / q_d / (chi2 / static_cast<double>(n - p)) > f_upper_quantile(p0, q_d, static_cast<double>(n - p));
    return dchi > chi2_upper_quantile(p0, q_d);
  };

  for (std::size_t q = 0; q < kNamedPatterns.size(); ++q) {
    const NamedPattern pat = kNamedPatterns[q];
    PatternTrend& t = out.trends[q];
    t.pattern = pat;
    t.teeth = order.size();
    Eigen::VectorXd y(n), s(n), j(n), th(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto& f = flanks[order[static_cast<std::size_t>(i)]];
      const Estimate e = pattern_value(f, pat);
      y(i) = e.value;
      s(i) = e.standard_error;
      j(i) = f.tooth;
      th(i) = kTwoPi * (f.tooth - 1) / teeth_in_gear;
    }
    const auto c0 = weighted_fit(Eigen::MatrixXd::Ones(n, 1), y, s);
    t.mean_um = {c0->coef(0), std::sqrt(c0->cov(0, 0) * birge(c0->chi2, 1))};
    t.chi2_constant = c0->chi2;
    const std::string pname(to_string(pat));
    const std::string mean_text = fmt::format("mean {} ± {:.2f} µm", signed_um(t.mean_um.value),
                                              t.mean_um.standard_error);

    if (n == 2) {
      t.tooth_a = static_cast<int>(j(0));
      t.tooth_b = static_cast<int>(j(1));
      t.difference_um = {y(1) - y(0), std::hypot(s(0), s(1))};
      const bool sig = std::abs(t.difference_um.value) > k * t.difference_um.standard_error;
      t.kind = sig ? TrendKind::Difference : TrendKind::Constant;
      t.sentence = sig ? fmt::format("{}: differs by {} ± {:.2f} µm between tooth {} and tooth {} ({} flanks)", pname,
                                     signed_um(t.difference_um.value), t.difference_um.standard_error, t.tooth_a,
                                     t.tooth_b, to_string(side))
                       : fmt::format("{}: tooth {} and tooth {} agree within {:g} standard errors (difference {} ± "
                                     "{:.2f} µm), {}",
                                     pname, t.tooth_a, t.tooth_b, k, signed_um(t.difference_um.value),
                                     t.difference_um.standard_error, mean_text);
      continue;
    }

    // Linear in tooth number (centred for conditioning).
    Eigen::MatrixXd XL(n, 2);
    XL.col(0).setOnes();
    XL.col(1) = j.array() - j.mean();
    const auto lin = weighted_fit(XL, y, s); // distinct teeth: always full rank
    t.slope_um_per_tooth = {lin->coef(1), std::sqrt(lin->cov(1, 1) * birge(lin->chi2, 2))};
    t.linear_significant = significant(c0->chi2 - lin->chi2, 1, lin->chi2, 2);

    // Once per revolution.
    Eigen::MatrixXd XS(n, 3);
    XS.col(0).setOnes();
    XS.col(1) = th.array().cos();
    XS.col(2) = th.array().sin();
    const auto sin_fit = weighted_fit(XS, y, s);
    if (sin_fit) {
      t.sinusoid_fitted = true;
      amplitude_phase(sin_fit->coef(1), sin_fit->coef(2), sin_fit->cov.block<2, 2>(1, 1) * birge(sin_fit->chi2, 3),
                      t.amplitude_um, t.phase_rad);
      t.max_at_tooth = 1.0 + t.phase_rad.value * teeth_in_gear / kTwoPi;
      t.sinusoid_significant = significant(c0->chi2 - sin_fit->chi2, 2, sin_fit->chi2, 3);
    }

    double chi2_model = c0->chi2;
    Eigen::Index params = 1;
    if (t.linear_significant &&
        !(t.sinusoid_significant && significant(lin->chi2 - sin_fit->chi2, 1, sin_fit->chi2, 3))) {
      t.kind = TrendKind::Linear; // the simpler model unless the sinusoid explains significantly more
      chi2_model = lin->chi2;
      params = 2;
    } else if (t.sinusoid_significant) {
      t.kind = TrendKind::OncePerRevolution;
      chi2_model = sin_fit->chi2;
      params = 3;
    } else {
      t.kind = c0->chi2 > chi2_upper_quantile(p0, static_cast<double>(n - 1)) ? TrendKind::Irregular
                                                                              : TrendKind::Constant;
    }
    if (t.kind == TrendKind::Linear || t.kind == TrendKind::OncePerRevolution)
      t.scatter_beyond_model =
          n > params && chi2_model > chi2_upper_quantile(p0, static_cast<double>(n - params));

    const std::string scatter = t.scatter_beyond_model ? ", plus tooth-to-tooth scatter beyond the standard errors" : "";
    switch (t.kind) {
    case TrendKind::Constant:
      t.sentence = fmt::format("{}: constant over {}, {}", pname, teeth_text, mean_text);
      break;
    case TrendKind::Linear:
      t.sentence = fmt::format("{}: linear trend {} ± {:.3f} µm per tooth over {} (teeth {}–{}), {}{}", pname,
                               signed_um(t.slope_um_per_tooth.value, 3), t.slope_um_per_tooth.standard_error,
                               teeth_text, out.teeth.front(), out.teeth.back(), mean_text, scatter);
      break;
    case TrendKind::OncePerRevolution:
      t.sentence = fmt::format("{}: once per revolution over {}, amplitude {:.2f} ± {:.2f} µm, largest near tooth "
                               "{:.1f} (tooth angle {:.1f}°), {}{}",
                               pname, teeth_text, t.amplitude_um.value, t.amplitude_um.standard_error, t.max_at_tooth,
                               t.phase_rad.value * 180.0 / std::numbers::pi, mean_text, scatter);
      break;
    case TrendKind::Irregular: {
      const double sd = std::sqrt((y.array() - y.mean()).square().sum() / static_cast<double>(n - 1));
      t.sentence = fmt::format("{}: varies from tooth to tooth over {} (standard deviation {:.2f} µm) beyond the "
                               "standard errors, without a linear or once-per-revolution trend; {}",
                               pname, teeth_text, sd, mean_text);
      break;
    }
    case TrendKind::Difference: break; // two teeth only, handled above
    }
  }
  return out;
}

// ===================================================================================================== 3. regions

namespace {

ProfileZone profile_zone(double lo, double hi) {
  constexpr double t = 1.0 / 3.0, eps = 1e-9;
  const double span = hi - lo, centre = 0.5 * (lo + hi);
  if (span >= 1.5 && std::abs(centre) <= 0.25) return ProfileZone::Whole;
  if (hi <= -t + eps) return ProfileZone::RootThird;
  if (lo >= t - eps) return ProfileZone::TipThird;
  if (lo >= -t - eps && hi <= t + eps) return ProfileZone::Middle;
  if (hi <= eps) return ProfileZone::RootHalf;
  if (lo >= -eps) return ProfileZone::TipHalf;
  return centre < 0 ? ProfileZone::RootHalf : ProfileZone::TipHalf;
}

AxialZone axial_zone(double lo, double hi) {
  switch (profile_zone(lo, hi)) { // same rule: root ↔ datum face (w = −1), tip ↔ far face (w = +1)
  case ProfileZone::RootThird: return AxialZone::DatumFaceEnd;
  case ProfileZone::Middle: return AxialZone::Middle;
  case ProfileZone::TipThird: return AxialZone::FarFaceEnd;
  case ProfileZone::RootHalf: return AxialZone::DatumFaceHalf;
  case ProfileZone::TipHalf: return AxialZone::FarFaceHalf;
  case ProfileZone::Whole: return AxialZone::Whole;
  }
  return AxialZone::Whole;
}

/// Neighbour lists of the in-range points: 8-neighbours when the points form a (mostly filled) grid, else all points
/// within 3 × the median nearest-neighbour distance in (u, w).
std::vector<std::vector<std::size_t>> neighbours(const Prepared& p, const FlankResiduals& f) {
  const std::size_t n = p.size();
  std::vector<std::vector<std::size_t>> nb(n);
  const auto dxi = distinct(p.xi, 1e-6 * (f.xi_end_mm - f.xi_start_mm));
  const auto dz = distinct(p.z, 1e-6 * (f.z_end_mm - f.z_start_mm));
  const auto cell_of = [](const std::vector<double>& d, double v) {
    auto it = std::upper_bound(d.begin(), d.end(), v); // the cluster whose first value is ≤ v
    return static_cast<long>(it - d.begin()) - 1;
  };
  if (dxi.size() * dz.size() <= 2 * n) {
    std::map<std::pair<long, long>, std::size_t> cells;
    bool unique = true;
    std::vector<std::pair<long, long>> at(n);
    for (std::size_t i = 0; i < n && unique; ++i) {
      at[i] = {cell_of(dxi, p.xi[i]), cell_of(dz, p.z[i])};
      unique = cells.emplace(at[i], i).second;
    }
    if (unique) {
      for (std::size_t i = 0; i < n; ++i)
        for (long di = -1; di <= 1; ++di)
          for (long dk = -1; dk <= 1; ++dk) {
            if (di == 0 && dk == 0) continue;
            auto it = cells.find({at[i].first + di, at[i].second + dk});
            if (it != cells.end()) nb[i].push_back(it->second);
          }
      return nb;
    }
  }
  if (n < 2) return nb;
  // Scattered points (a point cloud): buckets of about two points each in (u, w) ∈ [−1, 1]², so that both searches
  // look at a few buckets per point instead of all n points (a 20 000-point flank took 19 s that way).
  const long side = std::max(1L, static_cast<long>(std::sqrt(static_cast<double>(n) / 2.0)));
  const double h = 2.0 / static_cast<double>(side);
  const auto bucket = [&](double v) { return std::clamp(static_cast<long>((v + 1.0) / h), 0L, side - 1); };
  std::vector<std::vector<std::size_t>> grid(static_cast<std::size_t>(side * side));
  for (std::size_t i = 0; i < n; ++i) grid[static_cast<std::size_t>(bucket(p.u[i]) * side + bucket(p.w[i]))].push_back(i);
  const auto dist = [&](std::size_t i, std::size_t k) { return std::hypot(p.u[i] - p.u[k], p.w[i] - p.w[k]); };
  // Calls f(k) for every point in the buckets within `ring` buckets of point i's, ring by ring from 0 to `rings`.
  const auto visit_ring = [&](std::size_t i, long ring, const auto& f) {
    const long bu = bucket(p.u[i]), bw = bucket(p.w[i]);
    for (long a = bu - ring; a <= bu + ring; ++a)
      for (long b = bw - ring; b <= bw + ring; ++b) {
        if (std::max(std::abs(a - bu), std::abs(b - bw)) != ring || a < 0 || b < 0 || a >= side || b >= side) continue;
        for (std::size_t k : grid[static_cast<std::size_t>(a * side + b)]) f(k);
      }
  };
  // Nearest neighbour: rings outward until the next ring cannot hold anything closer (a point in ring r is at least
  // (r − 1)·h away).
  std::vector<double> nn(n, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < n; ++i)
    for (long ring = 0; ring < side && !(nn[i] <= static_cast<double>(ring - 1) * h); ++ring)
      visit_ring(i, ring, [&](std::size_t k) {
        if (k != i) nn[i] = std::min(nn[i], dist(i, k));
      });
  std::vector<double> sorted = nn;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(n / 2), sorted.end());
  const double link = 3.0 * sorted[n / 2];
  const long reach = std::min(side - 1, static_cast<long>(std::ceil(link / h)) + 1);
  for (std::size_t i = 0; i < n; ++i) {
    for (long ring = 0; ring <= reach; ++ring)
      visit_ring(i, ring, [&](std::size_t k) {
        if (k != i && dist(i, k) <= link) nb[i].push_back(k);
      });
    std::sort(nb[i].begin(), nb[i].end()); // the order of the former all-pairs scan
  }
  return nb;
}

} // namespace

std::vector<FailingRegion> find_failing_regions(const FlankResiduals& flank, const RegionOptions& o) {
  constexpr std::string_view what = "failing-region search";
  check_noise(what, o.noise_um);
  if (!(o.k > 0.0 && std::isfinite(o.k))) refuse(what, fmt::format("threshold factor k = {} (must be > 0)", o.k));
  const Prepared p = prepare(flank, what);
  const double sigma = o.noise_um, limit = o.k * sigma;
  const std::size_t n = p.size();

  std::vector<int> mark(n, 0); // +1 / −1 failing by sign, 0 passing
  bool any = false;
  for (std::size_t i = 0; i < n; ++i)
    if (std::abs(p.r[i]) > limit) {
      mark[i] = p.r[i] > 0 ? +1 : -1;
      any = true;
    }
  std::vector<FailingRegion> regions;
  if (!any) return regions;
  const auto nb = neighbours(p, flank);

  std::vector<bool> seen(n, false);
  for (std::size_t start = 0; start < n; ++start) {
    if (mark[start] == 0 || seen[start]) continue;
    std::vector<std::size_t> members{start}; // local indices
    seen[start] = true;
    for (std::size_t q = 0; q < members.size(); ++q)
      for (std::size_t k : nb[members[q]])
        if (!seen[k] && mark[k] == mark[start]) {
          seen[k] = true;
          members.push_back(k);
        }
    if (members.size() < o.min_points) continue;
    std::sort(members.begin(), members.end());

    FailingRegion g;
    g.tooth = flank.tooth;
    g.side = flank.side;
    g.sign = mark[start];
    double ulo = 1e300, uhi = -1e300, wlo = 1e300, whi = -1e300, sum = 0.0, sum_abs = 0.0;
    g.xi_min_mm = g.z_min_mm = 1e300;
    g.xi_max_mm = g.z_max_mm = -1e300;
    std::size_t ext = members.front();
    for (std::size_t i : members) {
      g.point_indices.push_back(p.index[i]);
      if (std::abs(p.r[i]) > std::abs(p.r[ext])) ext = i;
      sum += p.r[i];
      sum_abs += std::abs(p.r[i]);
      ulo = std::min(ulo, p.u[i]);
      uhi = std::max(uhi, p.u[i]);
      wlo = std::min(wlo, p.w[i]);
      whi = std::max(whi, p.w[i]);
      g.xi_min_mm = std::min(g.xi_min_mm, p.xi[i]);
      g.xi_max_mm = std::max(g.xi_max_mm, p.xi[i]);
      g.z_min_mm = std::min(g.z_min_mm, p.z[i]);
      g.z_max_mm = std::max(g.z_max_mm, p.z[i]);
    }
    const double m = static_cast<double>(members.size());
    g.mean_um = sum / m;
    const double mean_abs = sum_abs / m;
    g.extreme_um = p.r[ext];
    g.extreme_index = p.index[ext];
    g.extreme_xi_mm = p.xi[ext];
    g.extreme_z_mm = p.z[ext];
    g.profile_zone = profile_zone(ulo, uhi);
    g.axial_zone = axial_zone(wlo, whi);

    // Tendency: plane fit of |residual| (= sign · residual) over the region, in mm about the region's centre.
    const double span_xi = g.xi_max_mm - g.xi_min_mm, span_z = g.z_max_mm - g.z_min_mm;
    const double cxi = 0.5 * (g.xi_min_mm + g.xi_max_mm), cz = 0.5 * (g.z_min_mm + g.z_max_mm);
    bool use_xi = span_xi > 1e-9, use_z = span_z > 1e-9;
    const auto mi = static_cast<Eigen::Index>(members.size());
    Eigen::VectorXd ya(mi);
    for (Eigen::Index i = 0; i < mi; ++i) ya(i) = g.sign * p.r[members[static_cast<std::size_t>(i)]];
    std::optional<LsFit> plane;
    for (int attempt = 0; attempt < 3; ++attempt) {
      Eigen::MatrixXd X(mi, 1 + (use_xi ? 1 : 0) + (use_z ? 1 : 0));
      for (Eigen::Index i = 0; i < mi; ++i) {
        const std::size_t l = members[static_cast<std::size_t>(i)];
        Eigen::Index c = 0;
        X(i, c++) = 1.0;
        if (use_xi) X(i, c++) = (p.xi[l] - cxi) / std::max(span_xi, 1e-300);
        if (use_z) X(i, c++) = (p.z[l] - cz) / std::max(span_z, 1e-300);
      }
      plane = least_squares(X, ya);
      if (plane) break;
      // Not determined (too few points, or they lie on a slanted line): drop the direction of smaller relative extent.
      if (use_xi && use_z) {
        if ((uhi - ulo) < (whi - wlo)) use_xi = false;
        else use_z = false;
      } else {
        use_xi = use_z = false;
      }
    }
    if (plane) {
      Eigen::Index c = 1;
      const auto judge = [&](double& change) {
        change = plane->coef(c);
        const double se = sigma * std::sqrt(plane->cov_unit(c, c));
        ++c;
        return std::abs(change) > kTendencySigmas * se && std::abs(change) > kTendencyFraction * mean_abs;
      };
      if (use_xi && judge(g.change_along_profile_um))
        g.profile_growth = g.change_along_profile_um > 0 ? ProfileGrowth::TowardsTip : ProfileGrowth::TowardsRoot;
      if (use_z && judge(g.change_along_face_um))
        g.axial_growth = g.change_along_face_um > 0 ? AxialGrowth::TowardsFarFace : AxialGrowth::TowardsDatumFace;
      const double rms_plane = std::sqrt(plane->rss / m);
      g.peaked = g.profile_growth == ProfileGrowth::None && g.axial_growth == AxialGrowth::None && mi >= 4 &&
                 rms_plane > std::max(2.0 * sigma, kTendencyFraction * mean_abs);
    }

    // Words.
    const std::string where = g.profile_zone == ProfileZone::Whole && g.axial_zone == AxialZone::Whole
                                  ? std::string("whole flank")
                                  : fmt::format("{}, {}", to_string(g.profile_zone), to_string(g.axial_zone));
    const std::string thick = g.sign > 0 ? "thicker (plus material)" : "thinner (minus material)";
    std::string trend;
    if (g.profile_growth != ProfileGrowth::None || g.axial_growth != AxialGrowth::None) {
      std::vector<std::string> dirs;
      if (g.profile_growth != ProfileGrowth::None)
        dirs.emplace_back(g.profile_growth == ProfileGrowth::TowardsTip ? "the tip" : "the root");
      if (g.axial_growth != AxialGrowth::None)
        dirs.emplace_back(g.axial_growth == AxialGrowth::TowardsFarFace ? "the far face" : "the datum face");
      trend = "growing towards " + dirs.front() + (dirs.size() > 1 ? " and " + dirs.back() : "");
    } else if (g.peaked) {
      trend = g.sign > 0 ? "local bump" : "local hollow";
    } else {
      trend = "uniform";
    }
    const std::string extreme = fmt::format("extreme {} at ξ = {:.2f} mm, z = {:.2f} mm", signed_um(g.extreme_um, 1),
                                            g.extreme_xi_mm, g.extreme_z_mm);
    const std::string count = fmt::format("{} point{}", members.size(), members.size() == 1 ? "" : "s");
    if (trend == "uniform") {
      g.words = fmt::format("{}, uniform {}, {}", where, signed_um(g.mean_um, 1), thick);
      g.sentence = fmt::format("{}, {}: uniform {}, {}; {}; {}", flank_name(g.tooth, g.side), where,
                               signed_um(g.mean_um, 1), thick, extreme, count);
    } else {
      g.words = fmt::format("{}, {}, {}", where, thick, trend);
      g.sentence = fmt::format("{}, {}: {}, {}, up to {} at ξ = {:.2f} mm, z = {:.2f} mm; {}",
                               flank_name(g.tooth, g.side), where, thick, trend, signed_um(g.extreme_um, 1),
                               g.extreme_xi_mm, g.extreme_z_mm, count);
    }
    regions.push_back(std::move(g));
  }
  std::stable_sort(regions.begin(), regions.end(), [](const FailingRegion& a, const FailingRegion& b) {
    return std::abs(a.extreme_um) > std::abs(b.extreme_um);
  });
  return regions;
}

// ===================================================================================================== 4. statistics

namespace {

struct Accumulator {
  std::size_t n = 0;
  double sum_sq = 0.0;
  ResidualStats best;
  void add(int tooth, Flank side, double xi, double z, double r) {
    ++n;
    sum_sq += r * r;
    if (n == 1 || std::abs(r) > best.max_abs_um) {
      best.max_abs_um = std::abs(r);
      best.extreme_um = r;
      best.extreme_tooth = tooth;
      best.extreme_side = side;
      best.extreme_xi_mm = xi;
      best.extreme_z_mm = z;
    }
  }
  void add(const Accumulator& o) {
    if (o.n == 0) return;
    if (n == 0 || o.best.max_abs_um > best.max_abs_um) best = o.best;
    n += o.n;
    sum_sq += o.sum_sq;
  }
  ResidualStats stats() const {
    ResidualStats s = best;
    s.points = n;
    s.rms_um = n ? std::sqrt(sum_sq / static_cast<double>(n)) : 0.0;
    return s;
  }
};

} // namespace

ResidualSummary summarize_residuals(std::span<const FlankResiduals> flanks) {
  constexpr std::string_view what = "residual summary";
  if (flanks.empty()) refuse(what, "no flanks");
  std::map<std::pair<int, int>, std::pair<Accumulator, std::size_t>> per_flank; // (tooth, 0 left / 1 right)
  for (const auto& f : flanks) {
    const Prepared p = prepare(f, what);
    const std::pair<int, int> key{f.tooth, f.side == Flank::Left ? 0 : 1};
    if (per_flank.count(key)) refuse(what, fmt::format("{} given twice", flank_name(f.tooth, f.side)));
    Accumulator a;
    for (std::size_t i = 0; i < p.size(); ++i) a.add(f.tooth, f.side, p.xi[i], p.z[i], p.r[i]);
    per_flank.emplace(key, std::make_pair(a, p.outside));
  }
  ResidualSummary out;
  std::map<int, Accumulator> per_tooth;
  std::array<Accumulator, 2> per_side;
  std::array<std::size_t, 2> side_flanks{0, 0};
  Accumulator all;
  for (const auto& [key, v] : per_flank) {
    const Flank side = key.second == 0 ? Flank::Left : Flank::Right;
    out.flanks.push_back({key.first, side, v.second, v.first.stats()});
    per_tooth[key.first].add(v.first);
    per_side[static_cast<std::size_t>(key.second)].add(v.first);
    ++side_flanks[static_cast<std::size_t>(key.second)];
    all.add(v.first);
  }
  for (const auto& [tooth, a] : per_tooth) out.teeth.push_back({tooth, a.stats()});
  for (std::size_t s = 0; s < 2; ++s)
    if (side_flanks[s]) out.sides.push_back({s == 0 ? Flank::Left : Flank::Right, side_flanks[s], per_side[s].stats()});
  out.overall = all.stats();
  return out;
}

} // namespace geartopo::evaluation
