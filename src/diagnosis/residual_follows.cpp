// geartopo — the residual against the process variables (residual_follows.hpp). Units: µm, min, strokes, mm, °.
#include "geartopo/diagnosis/residual_follows.hpp"

#include "setup_terms.hpp"

#include "geartopo/core/uncertain_value.hpp"
#include "geartopo/diagnosis/effect_contribution.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace geartopo::diagnosis {

ResidualFollows residual_dependence(const grinding::GrindingSetup& setup,
                                                   const std::vector<measurement::MeasuredPoint>& pts,
                                                   const std::vector<double>& residual_um, double bic_threshold,
                                                   int threads) {
  if (pts.size() < 4) throw std::invalid_argument("residual dependence: at least 4 measured points are needed");
  if (residual_um.size() != pts.size())
    throw std::invalid_argument("residual dependence: one residual per measured point is needed");
  const auto n = static_cast<Eigen::Index>(pts.size());
  // Each point's generating pose (the contact does not depend on the process): its time, stroke, Z, C and the wheel
  // radius that touched it.
  const EffectContribution at(setup, pts, threads);
  const SetupTermModel st(setup.geometry(), pts);
  const Eigen::VectorXd y = st.remove(Eigen::Map<const Eigen::VectorXd>(residual_um.data(), n));
  const double rss0 = y.squaredNorm(), ln_n = std::log(static_cast<double>(n));

  struct Variable {
    std::string name, unit;
    bool periodic = false;
    std::vector<double> values;
  };
  std::vector<Variable> vars{{"grinding time", "min", false, {}},
                             {"stroke order", "stroke", false, {}},
                             {"stroke position Z", "mm", false, {}},
                             {"C angle", "deg", true, {}},
                             {"wheel radius", "mm", false, {}}};
  for (auto& v : vars) v.values.resize(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    const auto& pp = at.path_point(i);
    vars[0].values[i] = pp.time_s / 60.0;
    vars[1].values[i] = setup.path().stroke_index(pp.space) + 1.0;
    vars[2].values[i] = pp.z_stroke_mm;
    vars[3].values[i] = pp.q.c * 180.0 / std::numbers::pi;
    vars[4].values[i] = setup.wheel().radius(at.wheel_axial_mm(i));
  }

  ResidualFollows result;
  result.residual_setup_removed_um.assign(y.data(), y.data() + y.size());
  std::vector<ProcessDependence>& out = result.variables;
  for (auto& v : vars) {
    const auto [lo, hi] = std::minmax_element(v.values.begin(), v.values.end());
    if (!(*hi - *lo > 1e-9 * std::max(1.0, std::abs(*hi)))) continue; // it does not vary over these points
    ProcessDependence d;
    d.variable = v.name, d.unit = v.unit, d.once_per_revolution = v.periodic, d.lo = *lo, d.hi = *hi;
    Eigen::MatrixXd X(n, v.periodic ? 2 : 1);
    const double mid = 0.5 * (*lo + *hi);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double x = v.values[static_cast<size_t>(i)];
      if (v.periodic) {
        X(i, 0) = std::cos(x * std::numbers::pi / 180.0), X(i, 1) = std::sin(x * std::numbers::pi / 180.0);
      } else {
        X(i, 0) = x - mid;
      }
    }
    Eigen::MatrixXd Xp(n, X.cols());
    for (Eigen::Index j = 0; j < X.cols(); ++j) Xp.col(j) = st.remove(Eigen::VectorXd(X.col(j)));
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Xp);
    if (qr.rank() < Xp.cols() || rss0 <= 0.0) continue; // the set-up terms hold it already (one C angle per side)
    const Eigen::VectorXd beta = qr.solve(y);
    const double rss = (y - Xp * beta).squaredNorm();
    const double p = static_cast<double>(X.cols());
    const double sigma2 = rss / std::max(1.0, static_cast<double>(n) - st.count() - p);
    const Eigen::MatrixXd cov = sigma2 * (Xp.transpose() * Xp).inverse();
    if (v.periodic) {
      // a·cos(γ − φ): a = |β|, φ = atan2(β₁, β₀); δa = gᵀδβ, δφ = hᵀδβ / a, g = (cos φ, sin φ), h = (−sin φ, cos φ).
      const double a = beta.norm(), phi = std::atan2(beta(1), beta(0));
      const Eigen::Vector2d g(std::cos(phi), std::sin(phi)), h(-g(1), g(0));
      d.slope_um = a, d.slope_sd_um = std::sqrt(g.dot(cov * g));
      d.phase_deg = phi * 180.0 / std::numbers::pi;
      d.phase_sd_deg = a > 0.0 ? std::sqrt(h.dot(cov * h)) / a * 180.0 / std::numbers::pi : 180.0;
    } else {
      d.slope_um = beta(0), d.slope_sd_um = std::sqrt(cov(0, 0));
    }
    d.explained_fraction = 1.0 - rss / rss0;
    d.delta_bic = static_cast<double>(n) * std::log(std::max(rss, 1e-300) / rss0) + p * ln_n;
    d.significant = d.delta_bic < -bic_threshold;
    d.values = std::move(v.values);
    const std::string size = text::with_uncertainty(d.slope_um, d.slope_sd_um, !v.periodic);
    d.sentence = v.periodic
                     ? fmt::format("{}: {} µm once per revolution, largest at {}° (ΔBIC {:.1f}, {:.0f} % of the residual)",
                                   d.variable, size, text::with_uncertainty(d.phase_deg, d.phase_sd_deg), d.delta_bic,
                                   100.0 * d.explained_fraction)
                     : fmt::format("{}: {} µm/{} over {:.4g} … {:.4g} {} (ΔBIC {:.1f}, {:.0f} % of the residual)",
                                   d.variable, size, d.unit, d.lo, d.hi, d.unit, d.delta_bic, 100.0 * d.explained_fraction);
    out.push_back(std::move(d));
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.delta_bic < b.delta_bic; });
  return result;
}

} // namespace geartopo::diagnosis
