#include "geartopo/diagnosis/diagnose.hpp"

#include "effect_fit.hpp"

#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/effects/registry.hpp" // effect_types
#include "geartopo/workbench/workbench.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string_view>

namespace geartopo::diagnosis {
namespace {

/// Refuses options that would make the rules meaningless (the message names the option and its allowed range).
void check_options(const DiagnoseOptions& o) {
  const auto refuse = [](std::string_view name, double value, std::string_view rule) {
    throw std::invalid_argument(fmt::format("diagnose: option {} = {} (must be {})", name, value, rule));
  };
  if (!(std::isfinite(o.bic_threshold) && o.bic_threshold >= 0.0)) refuse("bic_threshold", o.bic_threshold, "finite and ≥ 0");
  if (o.min_points < 1) refuse("min_points", static_cast<double>(o.min_points), "≥ 1");
  if (!(std::isfinite(o.explained_noise_factor) && o.explained_noise_factor > 0.0))
    refuse("explained_noise_factor", o.explained_noise_factor, "finite and > 0");
  if (o.pair_candidates < 1) refuse("pair_candidates", static_cast<double>(o.pair_candidates), "≥ 1");
  if (!(std::isfinite(o.covariance_ridge) && o.covariance_ridge >= 0.0))
    refuse("covariance_ridge", o.covariance_ridge, "finite and ≥ 0");
  if (o.profile_walk_steps < 0) refuse("profile_walk_steps", o.profile_walk_steps, "≥ 0");
  if (!(std::isfinite(o.profile_min_step) && o.profile_min_step > 0.0))
    refuse("profile_min_step", o.profile_min_step, "finite and > 0");
}

} // namespace

std::string Candidate::name() const {
  std::string s;
  for (const auto& e : effects) s += (s.empty() ? "" : " + ") + e.type;
  return s;
}

double estimate_noise_um(const std::vector<MeasuredPoint>& pts, const std::vector<double>& r) {
  std::map<std::pair<int, int>, std::vector<size_t>> flanks;
  for (size_t i = 0; i < pts.size(); ++i) flanks[{pts[i].tooth, static_cast<int>(pts[i].flank)}].push_back(i);
  double rss = 0.0, dof = 0.0;
  for (const auto& [key, idx] : flanks) {
    if (idx.size() < 10) continue;
    double xlo = 1e300, xhi = -1e300, zlo = 1e300, zhi = -1e300;
    for (size_t i : idx) {
      xlo = std::min(xlo, pts[i].roll_length_mm), xhi = std::max(xhi, pts[i].roll_length_mm);
      zlo = std::min(zlo, pts[i].z_mm), zhi = std::max(zhi, pts[i].z_mm);
    }
    Eigen::MatrixXd X(static_cast<long>(idx.size()), 6);
    Eigen::VectorXd y(static_cast<long>(idx.size()));
    for (size_t k = 0; k < idx.size(); ++k) {
      const auto& p = pts[idx[k]];
      const double u = xhi > xlo ? 2 * (p.roll_length_mm - xlo) / (xhi - xlo) - 1 : 0.0;
      const double w = zhi > zlo ? 2 * (p.z_mm - zlo) / (zhi - zlo) - 1 : 0.0;
      X.row(static_cast<long>(k)) << 1.0, u, w, u * w, u * u, w * w;
      y(static_cast<long>(k)) = r[idx[k]];
    }
    const Eigen::VectorXd beta = X.colPivHouseholderQr().solve(y);
    rss += (y - X * beta).squaredNorm();
    dof += static_cast<double>(idx.size()) - 6.0;
  }
  constexpr double kFallbackNoiseUm = 0.1;
  return dof > 0.0 && rss > 0.0 ? std::sqrt(rss / dof) : kFallbackNoiseUm;
}

Diagnosis diagnose(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                   const std::vector<MeasuredPoint>& pts, const std::vector<std::string>& in_scene,
                   const DiagnoseOptions& o) {
  check_options(o);
  if (pts.size() < o.min_points)
    throw std::invalid_argument(fmt::format("diagnose: {} measured point(s); at least {} are needed", pts.size(), o.min_points));
  Diagnosis d;
  d.points = static_cast<int>(pts.size());
  const auto base = predict(setup, model, pts, grinding::Method::Exact, o.threads);
  d.residual_before_um.resize(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) d.residual_before_um[i] = pts[i].deviation_um - base[i];
  const double n = static_cast<double>(pts.size());
  d.rms_before_um = std::sqrt(sum_of_squares(d.residual_before_um) / n);
  d.noise_estimated = o.noise_um <= 0.0;
  d.noise_um = d.noise_estimated ? estimate_noise_um(pts, d.residual_before_um) : o.noise_um;

  // Candidates: the ones asked for, or every library effect; never one the scene already models (fitting it again
  // would stack two copies and write a scene that lists it twice), never one twice.
  const bool asked = !o.candidates.empty();
  std::vector<std::string> types;
  for (const auto& t : asked ? o.candidates : effects::effect_types()) {
    const bool modelled = std::find(in_scene.begin(), in_scene.end(), t) != in_scene.end();
    if (modelled && asked)
      throw std::invalid_argument(fmt::format("diagnose: candidate '{}' is already in the scene's effects", t));
    if (!modelled && std::find(types.begin(), types.end(), t) == types.end()) types.push_back(t);
  }

  std::map<std::string, std::vector<double>> fitted_values;
  for (const auto& t : types) {
    Candidate c = fit_effects(setup, pts, d.residual_before_um, {t}, {}, o);
    c.significant = c.delta_bic < -o.bic_threshold;
    fitted_values[t] = c.effects.front().values;
    d.ranked.push_back(std::move(c));
  }
  std::sort(d.ranked.begin(), d.ranked.end(), [](const Candidate& a, const Candidate& b) { return a.delta_bic < b.delta_bic; });

  if (!d.ranked.empty() && d.ranked.front().significant) {
    d.chosen = d.ranked.front();
    if (d.ranked.front().rms_after_um > o.explained_noise_factor * d.noise_um) {
      std::vector<std::string> top;
      for (const auto& c : d.ranked)
        if (c.significant && top.size() < o.pair_candidates) top.push_back(c.effects.front().type);
      // The best effect with each other significant one (warm-started from the single fits).
      for (size_t b = 1; b < top.size(); ++b) {
        Candidate c = fit_effects(setup, pts, d.residual_before_um, {top[0], top[b]}, fitted_values, o);
        c.significant = c.delta_bic < d.ranked.front().delta_bic - o.bic_threshold;
        if (c.significant && (!d.combination || c.delta_bic < d.combination->delta_bic)) d.combination = std::move(c);
      }
      if (d.combination) d.chosen = d.combination;
    }
  }

  // The residual with the chosen effects, by the exact simulation.
  d.residual_after_um = d.residual_before_um;
  if (d.chosen) {
    const auto effs = workbench::make_effects(d.chosen->effects, setup);
    const effects::EffectsProcess with(model, effs);
    const auto after = predict(setup, with, pts, grinding::Method::Exact, o.threads);
    for (size_t i = 0; i < pts.size(); ++i) d.residual_after_um[i] = pts[i].deviation_um - after[i];
    d.chosen->rms_after_um = std::sqrt(sum_of_squares(d.residual_after_um) / n);
  }

  const double rms_after = std::sqrt(sum_of_squares(d.residual_after_um) / n);
  if (!d.chosen) {
    d.verdict = fmt::format("No effect of the library explains the residual significantly (best: {}, ΔBIC {:.1f}). "
                            "The residual ({:.2f} µm RMS against {:.2f} µm noise) stays unexplained: see its pattern.",
                            d.ranked.empty() ? "none" : d.ranked.front().name(),
                            d.ranked.empty() ? 0.0 : d.ranked.front().delta_bic, d.rms_before_um, d.noise_um);
  } else {
    d.verdict = fmt::format("Missing: {}. Adding it takes the residual from {:.2f} to {:.2f} µm RMS (noise {:.2f} µm{}).",
                            d.chosen->name(), d.rms_before_um, rms_after, d.noise_um, d.noise_estimated ? ", estimated" : "");
    if (rms_after > o.explained_noise_factor * d.noise_um)
      d.verdict += fmt::format(" More than {:g}× the noise is left: part of the residual is still unexplained.",
                               o.explained_noise_factor);
  }
  return d;
}

} // namespace geartopo::diagnosis
