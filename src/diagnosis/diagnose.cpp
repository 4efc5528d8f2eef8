#include "geartopo/diagnosis/diagnose.hpp"

#include "geartopo/diagnosis/levenberg_marquardt.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

namespace geartopo::diagnosis {
namespace {

double rss_of(const std::vector<double>& r) {
  double s = 0.0;
  for (double v : r) s += v * v;
  return s;
}

// One fit of a set of effects: which parameters are free, their scales and bounds, and how to evaluate them.
class EffectFit {
public:
  EffectFit(const grinding::GrindingSetup& setup, const std::vector<MeasuredPoint>& pts, const std::vector<double>& r0,
            const std::vector<std::string>& types, int threads)
      : setup_(setup), pts_(pts), r0_(r0), threads_(threads) {
    for (const auto& t : types) {
      effects_.push_back(effects::make_effect(t));
      effects_.back()->bind(setup);
      const auto& params = effects_.back()->parameters();
      for (size_t k = 0; k < params.size(); ++k)
        if (params[k].fitted) free_.push_back({effects_.size() - 1, k});
    }
  }

  size_t size() const { return free_.size(); }
  const effects::ParameterSpec& spec(size_t j) const { return effects_[free_[j].first]->parameters()[free_[j].second]; }

  void set(const Eigen::VectorXd& x) {
    for (size_t j = 0; j < free_.size(); ++j) {
      auto values = effects_[free_[j].first]->values();
      values[free_[j].second] = x(static_cast<long>(j)) * spec(j).typical;
      effects_[free_[j].first]->set_values(values);
    }
  }

  /// Effects' first-order contribution at the points (µm).
  std::vector<double> contribution() const {
    const grinding::IdealProcess ideal;
    const effects::EffectsProcess p(ideal, effects_);
    return predict(setup_, p, pts_, grinding::Method::Linear, threads_);
  }

  Eigen::VectorXd residual(const Eigen::VectorXd& x) {
    set(x);
    const auto c = contribution();
    Eigen::VectorXd r(static_cast<long>(c.size()));
    for (size_t i = 0; i < c.size(); ++i) r(static_cast<long>(i)) = r0_[i] - c[i];
    return r;
  }

  std::vector<scene::EffectSpec> specs() const {
    std::vector<scene::EffectSpec> out;
    for (const auto& e : effects_) out.push_back({std::string(e->type()), e->values()});
    return out;
  }
  const std::vector<std::unique_ptr<effects::Effect>>& effects() const { return effects_; }

  /// Index in free_ of (effect e, parameter k), or −1.
  int free_index(size_t e, size_t k) const {
    for (size_t j = 0; j < free_.size(); ++j)
      if (free_[j].first == e && free_[j].second == k) return static_cast<int>(j);
    return -1;
  }

private:
  const grinding::GrindingSetup& setup_;
  const std::vector<MeasuredPoint>& pts_;
  const std::vector<double>& r0_;
  int threads_;
  std::vector<std::unique_ptr<effects::Effect>> effects_;
  std::vector<std::pair<size_t, size_t>> free_; // (effect, parameter)
};

// Fits the effects from every combination of start values of their nonlinear parameters (and from `warm`, if given:
// values of a previous fit per type). Returns the candidate with the smallest RSS.
Candidate fit(const grinding::GrindingSetup& setup, const std::vector<MeasuredPoint>& pts, const std::vector<double>& r0,
              const std::vector<std::string>& types, const std::map<std::string, std::vector<double>>& warm, int threads) {
  EffectFit f(setup, pts, r0, types, threads);
  const long p = static_cast<long>(f.size());
  Eigen::VectorXd lo(p), hi(p), x0(p);
  std::vector<std::vector<double>> starts;
  for (long j = 0; j < p; ++j) {
    const auto& s = f.spec(static_cast<size_t>(j));
    lo(j) = s.lo / s.typical;
    hi(j) = s.hi / s.typical;
    x0(j) = (s.starts.empty() ? 0.0 : s.default_value) / s.typical;
    if (!s.starts.empty()) {
      std::vector<double> v;
      for (double st : s.starts) v.push_back(st / s.typical);
      starts.push_back(v);
    } else {
      starts.push_back({x0(j)});
    }
  }
  // Warm starts from earlier single fits (used for combinations).
  std::vector<Eigen::VectorXd> inits;
  Eigen::VectorXd w = x0;
  bool have_warm = false;
  for (size_t e = 0; e < f.effects().size(); ++e) {
    const auto it = warm.find(std::string(f.effects()[e]->type()));
    if (it == warm.end()) continue;
    for (size_t k = 0; k < it->second.size(); ++k) {
      const int j = f.free_index(e, k);
      if (j >= 0) w(j) = it->second[k] / f.spec(static_cast<size_t>(j)).typical, have_warm = true;
    }
  }
  if (have_warm) inits.push_back(w);
  // Cartesian product of the start lists (only nonlinear parameters have more than one start).
  std::vector<size_t> idx(starts.size(), 0);
  for (;;) {
    Eigen::VectorXd x(p);
    for (long j = 0; j < p; ++j) x(j) = starts[static_cast<size_t>(j)][idx[static_cast<size_t>(j)]];
    inits.push_back(x);
    long j = 0;
    for (; j < p; ++j) {
      if (++idx[static_cast<size_t>(j)] < starts[static_cast<size_t>(j)].size()) break;
      idx[static_cast<size_t>(j)] = 0;
    }
    if (j == p) break;
  }

  LmResult best;
  best.rss = std::numeric_limits<double>::infinity();
  for (const auto& init : inits) {
    const LmResult r = levenberg_marquardt([&](const Eigen::VectorXd& x) { return f.residual(x); }, init, lo, hi);
    if (r.rss < best.rss) best = r;
  }
  f.set(best.x);

  const double n = static_cast<double>(pts.size());
  const double rss0 = rss_of(r0);
  Candidate c;
  c.effects = f.specs();
  // Covariance σ̂² (JᵀJ)⁻¹ in scaled units; a tiny ridge keeps directions the data cannot see at huge variance
  // instead of a false zero.
  const double sigma2 = best.rss / std::max(1.0, n - static_cast<double>(p));
  Eigen::MatrixXd A = best.JtJ;
  A.diagonal().array() += 1e-12 * std::max(1.0, A.trace());
  const Eigen::MatrixXd cov = sigma2 * A.inverse();
  Eigen::VectorXd sd = cov.diagonal().cwiseMax(0.0).cwiseSqrt();
  // Nonlinear parameters (those with start lists, e.g. a time constant) make the linearised covariance optimistic:
  // the likelihood is not Gaussian in them. Walk each along its profile until the RSS has risen by σ̂² (the 1σ
  // profile-likelihood bound, doubling the step from the linearised σ), refit the others there, and widen every
  // uncertainty to cover how far the refit moved.
  for (long j = 0; j < p; ++j) {
    if (f.spec(static_cast<size_t>(j)).starts.empty()) continue;
    for (double sign : {-1.0, 1.0}) {
      double step = std::max(sd(j), 1e-6);
      for (int k = 0; k < 8; ++k, step *= 2.0) {
        Eigen::VectorXd lo_j = lo, hi_j = hi, x = best.x;
        x(j) = std::clamp(best.x(j) + sign * step, lo(j), hi(j));
        lo_j(j) = hi_j(j) = x(j);
        const LmResult r = levenberg_marquardt([&](const Eigen::VectorXd& y) { return f.residual(y); }, x, lo_j, hi_j);
        const bool reached = r.rss - best.rss >= sigma2 || x(j) == lo(j) || x(j) == hi(j);
        if (reached || k == 7) {
          sd = sd.cwiseMax((r.x - best.x).cwiseAbs());
          break;
        }
      }
    }
  }
  f.set(best.x);
  for (size_t e = 0; e < f.effects().size(); ++e) {
    const auto& eff = *f.effects()[e];
    std::vector<FittedParameter> params;
    for (size_t k = 0; k < eff.parameters().size(); ++k) {
      const int j = f.free_index(e, k);
      const double u = j >= 0 ? sd(j) * eff.parameters()[k].typical : 0.0;
      params.push_back({eff.parameters()[k].key, eff.value(k), u, j >= 0});
    }
    c.parameters.push_back(params);
    c.explanations.emplace_back(eff.explanation());
  }
  c.rms_before_um = std::sqrt(rss0 / n);
  c.rms_after_um = std::sqrt(best.rss / n);
  c.explained_fraction = rss0 > 0.0 ? 1.0 - best.rss / rss0 : 0.0;
  c.delta_bic = n * std::log(std::max(best.rss, 1e-300) / std::max(rss0, 1e-300)) + static_cast<double>(p) * std::log(n);
  return c;
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
  if (pts.size() < 10) throw std::invalid_argument("diagnose: at least 10 measured points are needed");
  Diagnosis d;
  d.points = static_cast<int>(pts.size());
  const auto base = predict(setup, model, pts, grinding::Method::Exact, o.threads);
  d.residual_before_um.resize(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) d.residual_before_um[i] = pts[i].deviation_um - base[i];
  const double n = static_cast<double>(pts.size());
  d.rms_before_um = std::sqrt(rss_of(d.residual_before_um) / n);
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
    Candidate c = fit(setup, pts, d.residual_before_um, {t}, {}, o.threads);
    c.significant = c.delta_bic < -o.bic_threshold;
    fitted_values[t] = c.effects.front().values;
    d.ranked.push_back(std::move(c));
  }
  std::sort(d.ranked.begin(), d.ranked.end(), [](const Candidate& a, const Candidate& b) { return a.delta_bic < b.delta_bic; });

  if (!d.ranked.empty() && d.ranked.front().significant) {
    d.chosen = d.ranked.front();
    if (d.ranked.front().rms_after_um > 1.5 * d.noise_um) {
      std::vector<std::string> top;
      for (const auto& c : d.ranked)
        if (c.significant && top.size() < 4) top.push_back(c.effects.front().type);
      // The best effect with each other significant one (warm-started from the single fits).
      for (size_t b = 1; b < top.size(); ++b) {
        Candidate c = fit(setup, pts, d.residual_before_um, {top[0], top[b]}, fitted_values, o.threads);
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
    d.chosen->rms_after_um = std::sqrt(rss_of(d.residual_after_um) / n);
  }

  const double rms_after = std::sqrt(rss_of(d.residual_after_um) / n);
  if (!d.chosen) {
    d.verdict = fmt::format("No effect of the library explains the residual significantly (best: {}, ΔBIC {:.1f}). "
                            "The residual ({:.2f} µm RMS against {:.2f} µm noise) stays unexplained: see its pattern.",
                            d.ranked.empty() ? "none" : d.ranked.front().name(),
                            d.ranked.empty() ? 0.0 : d.ranked.front().delta_bic, d.rms_before_um, d.noise_um);
  } else {
    d.verdict = fmt::format("Missing: {}. Adding it takes the residual from {:.2f} to {:.2f} µm RMS (noise {:.2f} µm{}).",
                            d.chosen->name(), d.rms_before_um, rms_after, d.noise_um, d.noise_estimated ? ", estimated" : "");
    if (rms_after > 1.5 * d.noise_um)
      d.verdict += " More than 1.5× the noise is left: part of the residual is still unexplained.";
  }
  return d;
}

} // namespace geartopo::diagnosis
