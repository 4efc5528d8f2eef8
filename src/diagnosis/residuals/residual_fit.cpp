// geartopo diagnosis — the shared helpers of the residual analysis (residual_fit.hpp).
#include "residuals/residual_fit.hpp"

#include "geartopo/evaluation/trace.hpp" // kRangeSlackMm: the one slack of every evaluation range

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace geartopo::diagnosis::residuals {

[[noreturn]] void refuse(std::string_view what, const std::string& why) {
  throw std::invalid_argument(fmt::format("{} refused: {}", what, why));
}

std::string flank_name(int tooth, Flank side) { return fmt::format("tooth {}, {} flank", tooth, to_string(side)); }

namespace {

void check_range(std::string_view what, const FlankResiduals& f, double a, double b, const char* name) {
  if (!std::isfinite(a) || !std::isfinite(b))
    refuse(what, fmt::format("{}: the {} range is not finite", flank_name(f.tooth, f.side), name));
  if (!(a < b))
    refuse(what, fmt::format("{}: the {} range [{}, {}] mm has no length (start must be below end)",
                             flank_name(f.tooth, f.side), name, a, b));
}

} // namespace

Prepared prepare(const FlankResiduals& f, std::string_view what) {
  if (f.tooth < 1) refuse(what, fmt::format("tooth number {} (teeth are numbered from 1)", f.tooth));
  check_range(what, f, f.xi_start_mm, f.xi_end_mm, "roll length (L_α)");
  check_range(what, f, f.z_start_mm, f.z_end_mm, "axial (L_β)");
  if (f.points.empty()) refuse(what, fmt::format("{}: no points", flank_name(f.tooth, f.side)));
  Prepared p;
  const double s = evaluation::kRangeSlackMm;
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
    refuse(what, fmt::format("{}: none of its {} points lies inside the evaluation ranges L_y [{}, {}] mm, z [{}, {}] mm",
                             flank_name(f.tooth, f.side), f.points.size(), f.xi_start_mm, f.xi_end_mm, f.z_start_mm,
                             f.z_end_mm));
  return p;
}

void check_noise(std::string_view what, double sigma) {
  if (!std::isfinite(sigma) || !(sigma > 0.0))
    refuse(what, fmt::format("noise level σ = {} µm (must be finite and > 0)", sigma));
}

std::vector<double> distinct(std::vector<double> v, double tol) {
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (double x : v)
    if (out.empty() || x - out.back() > tol) out.push_back(x);
  return out;
}

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

std::string signed_um(double v, int decimals) { return fmt::format("{:+.{}f} µm", v, decimals); }

} // namespace geartopo::diagnosis::residuals
