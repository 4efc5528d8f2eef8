// geartopo diagnosis — named patterns of one flank's residual (flank_patterns.hpp, docs/residual-patterns.md
// section 1). Units: mm (ξ, z, wavelengths), µm (residuals, patterns, σ), rad.
#include "geartopo/diagnosis/residuals/flank_patterns.hpp"

#include "geartopo/diagnosis/residuals/line_noise.hpp"
#include "residuals/residual_fit.hpp"
#include "residuals/waviness_scan.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <cmath>

namespace geartopo::diagnosis {

using namespace residuals;

namespace {

/// Design matrix (n × 6) of the Legendre basis 1, u, w, u·w, P2(u), P2(w) at the prepared points.
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

} // namespace

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

  // Traces (a flank with dense lines, line_noise.hpp) are scanned only along their dense lines' direction: a wave along
  // z read off a few profile lines at a few heights would be fitted to the lines' offsets (issue 28). Grids and clouds:
  // both directions, as the distinct positions allow.
  const DenseLineCount lines = dense_line_count(flank);
  const bool traces = lines.profile + lines.helix > 0;
  // Waviness: along z on the Legendre model, then along ξ with a significant z wave included. When both are found, z is
  // scanned once more with the ξ wave in the model (and ξ with that z wave): on traces the wave of the other direction,
  // unmodelled, pulls the first scan's wavelength (a 30 mm lead wave read as 29.4 mm beside a 9 mm profile wave).
  const Eigen::MatrixXd A0 = A;
  const auto scan = [&](WaveDirection dir, const Eigen::MatrixXd& base) {
    const bool helix = dir == WaveDirection::Helix;
    WavinessScan w;
    w.direction = dir;
    if (traces && (helix ? lines.helix : lines.profile) == 0) {
      w.no_dense_line = true;
      return w;
    }
    w = helix ? scan_waviness(dir, base, y, p.z, flank.z_start_mm, flank.z_end_mm, sigma, o)
              : scan_waviness(dir, base, y, p.xi, flank.xi_start_mm, flank.xi_end_mm, sigma, o);
    if (w.wave && !least_squares(helix ? with_wave(base, p.z, flank.z_start_mm, w.wave->wavelength_mm)
                                       : with_wave(base, p.xi, flank.xi_start_mm, w.wave->wavelength_mm),
                                 y))
      w.wave.reset();
    return w;
  };
  const auto plus_helix_wave = [&](const Eigen::MatrixXd& base) {
    return out.waviness_helix.wave ? with_wave(base, p.z, flank.z_start_mm, out.waviness_helix.wave->wavelength_mm) : base;
  };
  const auto plus_profile_wave = [&](const Eigen::MatrixXd& base) {
    return out.waviness_profile.wave ? with_wave(base, p.xi, flank.xi_start_mm, out.waviness_profile.wave->wavelength_mm)
                                     : base;
  };
  out.waviness_helix = scan(WaveDirection::Helix, A0);
  out.waviness_profile = scan(WaveDirection::Profile, plus_helix_wave(A0));
  if (out.waviness_helix.wave && out.waviness_profile.wave) {
    out.waviness_helix = scan(WaveDirection::Helix, plus_profile_wave(A0));
    out.waviness_profile = scan(WaveDirection::Profile, plus_helix_wave(A0));
  }
  A = plus_profile_wave(plus_helix_wave(A0)); // columns: Legendre, z wave, ξ wave (the order read below)
  if (!least_squares(A, y)) { // not expected: each wave was checked on its own
    out.waviness_profile.wave.reset();
    A = plus_helix_wave(A0);
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
  for (const WavinessScan* w : {&f.waviness_helix, &f.waviness_profile})
    if (w->no_dense_line) s += fmt::format(" waviness {} not scanned (no measured line in that direction);", to_string(w->direction));
  s += fmt::format(" RMS {:.2f} µm, unexplained {:.2f} µm (σ {:.2f} µm)", f.rms_residual_um, f.rms_unexplained_um,
                   f.noise_um);
  return s;
}
} // namespace geartopo::diagnosis
