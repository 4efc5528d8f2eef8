// geartopo diagnosis — fitting a set of effects to a residual (effect_fit.hpp, docs/diagnosis.md). Parameters are fitted
// in scaled units x = value / typical (order one, as Levenberg–Marquardt wants); every vector below of length p is in
// those units, p the number of fitted parameters.
#include "effect_fit.hpp"
#include "proportional_parameters.hpp"

#include "geartopo/diagnosis/levenberg_marquardt.hpp"
#include "geartopo/effects/registry.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

namespace geartopo::diagnosis {
namespace {

// One fit of a set of effects: which parameters are free, their scales and bounds, and how to evaluate them.
// The residual is linear in the effects' deviations, and the effects add independently, so
//   r(x) = remove(r0 − offset) − Σ_e remove(d_e(θ_e))        (remove: the set-up terms' projection, whitened with GLS)
// is formed from one judged deviation remove(d_e) per effect, each kept until its own parameters change (a pair's
// finite-difference column of one effect does not re-evaluate the other). Where an effect's deviation is proportional
// to some of its parameters (ParameterSpec::linear), d_e = Σ_k θ_k b_k with b_k its deviation per unit of θ_k at the
// other parameters' values: the columns remove(b_k) are formed once for those values, after which d_e is a weighted
// sum of them (no hooks evaluated) and ∂r/∂θ_k = −remove(b_k) is the Jacobian column in closed form.
class EffectFit {
public:
  /// `project`: a user's law's proportional parameters are solved by variable projection (projected_residual).
  EffectFit(const grinding::GrindingSetup& setup, const EffectContribution& at_points, const std::vector<double>& r0,
            const std::vector<std::string>& types, const SetupTermModel& setup_terms, int threads, bool project,
            std::function<void()> keep_going)
      : at_points_(at_points), setup_terms_(setup_terms), threads_(threads), keep_going_(std::move(keep_going)) {
    const Eigen::Map<const Eigen::VectorXd> r(r0.data(), static_cast<Eigen::Index>(r0.size()));
    judged_r0_ = setup_terms.remove((r.array() - at_points.offset_um()).matrix());
    for (const auto& t : types) {
      effects_.push_back(effects::make_effect(t));
      effects_.back()->bind(setup);
      PerEffect c;
      c.scratch = effects_.back()->clone();
      c.all_fitted_linear = true;
      const auto& params = effects_.back()->parameters();
      // A user's law claims nothing: what it is proportional to is found at these points, and solved by projection.
      const std::vector<size_t> proportional = project && effects::is_custom_effect(t)
                                                   ? proportional_parameters(*effects_.back(), at_points, threads)
                                                   : std::vector<size_t>{};
      for (size_t k = 0; k < params.size(); ++k) {
        if (!params[k].fitted) continue;
        const bool found = std::find(proportional.begin(), proportional.end(), k) != proportional.end();
        if (found) projected_.push_back(static_cast<Eigen::Index>(free_.size()));
        else kept_.push_back(static_cast<Eigen::Index>(free_.size()));
        free_.push_back({effects_.size() - 1, k});
        if (params[k].linear || found) c.linear.push_back(k);
        else c.all_fitted_linear = false;
      }
      per_effect_.push_back(std::move(c));
    }
  }

  /// Free parameters solved by variable projection, and the others (indices into x, p scaled).
  const std::vector<Eigen::Index>& projected() const { return projected_; }
  const std::vector<Eigen::Index>& kept() const { return kept_; }

  /// Variable projection (Golub & Pereyra 1973): the residual with the kept parameters at xk (kept().size(), scaled)
  /// and the projected ones at their least-squares values within [lo, hi] for them — the residual is linear in those,
  /// r(x) = r_N − B θ with B their columns (n × |S|) at xk — written with xk into x (p, scaled).
  Eigen::VectorXd projected_residual(const Eigen::VectorXd& xk, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                                     Eigen::VectorXd& x) {
    x.setZero(static_cast<Eigen::Index>(free_.size()));
    for (size_t i = 0; i < kept_.size(); ++i) x(kept_[i]) = xk(static_cast<Eigen::Index>(i));
    set(x);
    Eigen::MatrixXd B(judged_r0_.size(), static_cast<Eigen::Index>(projected_.size())); // n × |S|, µm per scaled unit
    for (size_t m = 0; m < projected_.size(); ++m) {
      Eigen::VectorXd column;
      linear_column(x, projected_[m], column); // −remove(b_k)·typical, formed once per kept values
      B.col(static_cast<Eigen::Index>(m)) = -column;
    }
    const Eigen::VectorXd rN = residual(x); // the projected parameters at 0: their effects' share is B θ
    const Eigen::VectorXd theta = bounded_least_squares(B, rN, lo, hi);
    for (size_t m = 0; m < projected_.size(); ++m) x(projected_[m]) = theta(static_cast<Eigen::Index>(m));
    set(x);
    return rN - B * theta;
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

  /// Residual left at the points (µm, one per point) with the parameters x (p, scaled) and the best set-up terms for
  /// them (variable projection: the terms are linear, so they are solved exactly for every x).
  Eigen::VectorXd residual(const Eigen::VectorXd& x) {
    if (keep_going_) keep_going_(); // DiagnoseOptions::keep_going: a fit on 10⁵ points takes seconds
    set(x);
    Eigen::VectorXd r = judged_r0_;
    for (size_t e = 0; e < effects_.size(); ++e) r -= judged_deviation(e);
    return r;
  }

  /// The Jacobian column of a parameter the deviation is proportional to (n, µm per scaled unit): −remove(b_k)·typical;
  /// false for the others (finite differences).
  bool linear_column(const Eigen::VectorXd& x, Eigen::Index j, Eigen::VectorXd& column) {
    const auto [e, k] = free_[static_cast<size_t>(j)];
    const auto& linear = per_effect_[e].linear;
    const auto at = std::find(linear.begin(), linear.end(), k);
    if (at == linear.end()) return false;
    set(x);
    if (!columns_current(e)) form_columns(e);
    column = -spec(static_cast<size_t>(j)).typical * per_effect_[e].judged_columns.col(at - linear.begin());
    return true;
  }

  /// Levenberg–Marquardt from x0 within [lo, hi] (all p, scaled).
  /// With max_iterations 0: the residual's RSS and JᵀJ at x0 (clamped into the box).
  LmResult minimise(const Eigen::VectorXd& x0, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                    int max_iterations = 60) {
    return levenberg_marquardt([&](const Eigen::VectorXd& x) { return residual(x); }, x0, lo, hi, max_iterations,
                               [&](const Eigen::VectorXd& x, Eigen::Index j, Eigen::VectorXd& column) {
                                 return linear_column(x, j, column);
                               },
                               threads_);
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
  /// What is kept per effect between evaluations.
  struct PerEffect {
    std::unique_ptr<effects::Effect> scratch; ///< a copy, to evaluate the columns b_k on
    std::vector<size_t> linear;               ///< fitted parameters the deviation is proportional to
    bool all_fitted_linear = false;           ///< every fitted parameter is linear: the columns never change in a fit
    std::vector<double> columns_at;           ///< values the columns were formed at (linear entries unused); empty: none
    Eigen::MatrixXd judged_columns;           ///< n × linear.size(): remove(b_k), µm per file unit of θ_k
    std::vector<double> judged_at;            ///< values of the last judged deviation; empty: none
    Eigen::VectorXd judged;                   ///< n: remove(d_e) at judged_at (µm)
  };

  /// The columns were formed at the effect's current values of its other (not linear) parameters.
  bool columns_current(size_t e) const {
    const PerEffect& c = per_effect_[e];
    if (c.columns_at.empty()) return false;
    const auto& v = effects_[e]->values();
    for (size_t k = 0; k < v.size(); ++k)
      if (std::find(c.linear.begin(), c.linear.end(), k) == c.linear.end() && v[k] != c.columns_at[k]) return false;
    return true;
  }

  /// b_k: the effect's deviation with θ_k = 1 (its file unit), its other linear parameters 0 and the rest as they are.
  void form_columns(size_t e) {
    PerEffect& c = per_effect_[e];
    const auto& v = effects_[e]->values();
    c.judged_columns.resize(judged_r0_.size(), static_cast<Eigen::Index>(c.linear.size()));
    for (size_t m = 0; m < c.linear.size(); ++m) {
      std::vector<double> unit = v;
      for (size_t k : c.linear) unit[k] = 0.0;
      unit[c.linear[m]] = 1.0;
      c.scratch->set_values(std::move(unit));
      const effects::Effect* one[] = {c.scratch.get()};
      c.judged_columns.col(static_cast<Eigen::Index>(m)) = setup_terms_.remove(at_points_.deviation_um(one, threads_));
    }
    c.columns_at = v;
  }

  /// remove(d_e) at the effect's current values (n, µm).
  const Eigen::VectorXd& judged_deviation(size_t e) {
    PerEffect& c = per_effect_[e];
    const auto& v = effects_[e]->values();
    if (v == c.judged_at) return c.judged;
    if (!c.linear.empty() && c.all_fitted_linear && !columns_current(e)) form_columns(e); // once per fit
    if (!c.linear.empty() && columns_current(e)) {
      c.judged.setZero(judged_r0_.size()); // in place: no new allocation per evaluation
      for (size_t m = 0; m < c.linear.size(); ++m)
        c.judged += v[c.linear[m]] * c.judged_columns.col(static_cast<Eigen::Index>(m));
    } else {
      const effects::Effect* one[] = {effects_[e].get()};
      c.judged = setup_terms_.remove(at_points_.deviation_um(one, threads_));
    }
    c.judged_at = v;
    return c.judged;
  }

  /// min ‖r − B θ‖ with each θ_m within [lo, hi] of its parameter (scaled): unconstrained, then the worst value out of
  /// its range held at its bound and the rest solved again (at most |S| times; exact for one parameter).
  Eigen::VectorXd bounded_least_squares(const Eigen::MatrixXd& B, const Eigen::VectorXd& r, const Eigen::VectorXd& lo,
                                        const Eigen::VectorXd& hi) const {
    const Eigen::Index L = B.cols();
    Eigen::VectorXd theta = Eigen::VectorXd::Zero(L);
    std::vector<bool> held(static_cast<size_t>(L), false);
    for (Eigen::Index pass = 0; pass <= L; ++pass) {
      std::vector<Eigen::Index> open;
      Eigen::VectorXd rest = r;
      for (Eigen::Index m = 0; m < L; ++m)
        if (held[static_cast<size_t>(m)]) rest -= B.col(m) * theta(m);
        else open.push_back(m);
      if (open.empty()) break;
      Eigen::MatrixXd Bo(B.rows(), static_cast<Eigen::Index>(open.size()));
      for (size_t i = 0; i < open.size(); ++i) Bo.col(static_cast<Eigen::Index>(i)) = B.col(open[i]);
      const Eigen::VectorXd t = Bo.colPivHouseholderQr().solve(rest);
      Eigen::Index worst = -1;
      double beyond = 0.0;
      for (size_t i = 0; i < open.size(); ++i) {
        const Eigen::Index m = open[i], j = projected_[static_cast<size_t>(m)];
        theta(m) = t(static_cast<Eigen::Index>(i));
        const double out = std::max(lo(j) - theta(m), theta(m) - hi(j));
        if (out > beyond) beyond = out, worst = m;
      }
      if (worst < 0) break;
      const Eigen::Index j = projected_[static_cast<size_t>(worst)];
      theta(worst) = std::clamp(theta(worst), lo(j), hi(j));
      held[static_cast<size_t>(worst)] = true;
    }
    return theta;
  }

  const EffectContribution& at_points_;
  const SetupTermModel& setup_terms_;
  int threads_;
  std::function<void()> keep_going_; ///< DiagnoseOptions::keep_going (may be empty)
  Eigen::VectorXd judged_r0_; ///< n: remove(r0 − offset), µm
  std::vector<std::unique_ptr<effects::Effect>> effects_;
  std::vector<PerEffect> per_effect_;           // one per effect
  std::vector<std::pair<size_t, size_t>> free_; // (effect, parameter)
  std::vector<Eigen::Index> projected_, kept_;  // indices into free_: solved by projection, fitted by LM
};

/// Bounds of the fitted parameters and the default start (p each, scaled).
struct Box {
  Eigen::VectorXd lo, hi, x0;
};

Box parameter_box(const EffectFit& f) {
  const long p = static_cast<long>(f.size());
  Box b{Eigen::VectorXd(p), Eigen::VectorXd(p), Eigen::VectorXd(p)};
  for (long j = 0; j < p; ++j) {
    const auto& s = f.spec(static_cast<size_t>(j));
    b.lo(j) = s.lo / s.typical;
    b.hi(j) = s.hi / s.typical;
    b.x0(j) = (s.starts.empty() ? 0.0 : s.default_value) / s.typical;
  }
  return b;
}

/// Step 1a, multi-start: the warm start (values of earlier single fits, when `warm` has any of these types), then the
/// Cartesian product of the start lists (only nonlinear parameters have more than one start; a linear one starts at 0).
std::vector<Eigen::VectorXd> start_points(const EffectFit& f, const Box& box,
                                          const std::map<std::string, std::vector<double>>& warm) {
  const long p = static_cast<long>(f.size());
  std::vector<std::vector<double>> starts;
  for (long j = 0; j < p; ++j) {
    const auto& s = f.spec(static_cast<size_t>(j));
    if (!s.starts.empty()) {
      std::vector<double> v;
      for (double st : s.starts) v.push_back(st / s.typical);
      starts.push_back(v);
    } else {
      starts.push_back({box.x0(j)});
    }
  }
  std::vector<Eigen::VectorXd> inits;
  Eigen::VectorXd w = box.x0;
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
  return inits;
}

/// Step 1b with variable projection: Levenberg–Marquardt over the kept parameters alone from each start's kept values
/// (a start differing only in projected values is the same start), the projected ones solved for each; the best
/// solution's RSS and JᵀJ are then those of every parameter at it (no iteration: the full residual's minimum is the
/// projected one's), for the covariance and the rest of the fit as without projection.
LmResult best_of_projected_starts(EffectFit& f, const std::vector<Eigen::VectorXd>& inits, const Box& box, int threads) {
  const auto& kept = f.kept();
  const auto k = static_cast<Eigen::Index>(kept.size());
  Eigen::VectorXd lo(k), hi(k);
  for (Eigen::Index i = 0; i < k; ++i) lo(i) = box.lo(kept[static_cast<size_t>(i)]), hi(i) = box.hi(kept[static_cast<size_t>(i)]);
  std::vector<Eigen::VectorXd> starts;
  for (const auto& init : inits) {
    Eigen::VectorXd xk(k);
    for (Eigen::Index i = 0; i < k; ++i) xk(i) = init(kept[static_cast<size_t>(i)]);
    if (std::none_of(starts.begin(), starts.end(), [&](const Eigen::VectorXd& s) { return s == xk; })) starts.push_back(xk);
  }
  Eigen::VectorXd x, best_x;
  double best_rss = std::numeric_limits<double>::infinity();
  for (const auto& xk0 : starts) {
    const auto projected = [&](const Eigen::VectorXd& xk) { return f.projected_residual(xk, box.lo, box.hi, x); };
    const Eigen::VectorXd xk = k > 0 ? levenberg_marquardt(projected, xk0, lo, hi, 60, {}, threads).x : xk0;
    const double rss = projected(xk).squaredNorm(); // and x: the full parameters there
    if (rss < best_rss) best_rss = rss, best_x = x;
  }
  if (!std::isfinite(best_rss)) return {};
  return f.minimise(best_x, box.lo, box.hi, 0);
}

/// Step 1b: Levenberg–Marquardt from every start; the smallest RSS wins (the first of equals). With parameters to
/// project, by variable projection (best_of_projected_starts).
LmResult best_of_starts(EffectFit& f, const std::vector<Eigen::VectorXd>& inits, const Box& box, int threads) {
  LmResult best;
  best.rss = std::numeric_limits<double>::infinity();
  if (!f.projected().empty()) {
    best = best_of_projected_starts(f, inits, box, threads);
    if (best.x.size() == 0) best.rss = std::numeric_limits<double>::infinity();
  }
  for (const auto& init : f.projected().empty() ? inits : std::vector<Eigen::VectorXd>{}) {
    const LmResult r = f.minimise(init, box.lo, box.hi);
    if (r.rss < best.rss) best = r;
  }
  // Every start gave a non-finite RSS (a non-finite residual or prediction): there is no fit, and `best.x` is empty —
  // reading it was the crash of issue 18. Readers bound their inputs; this guards the fit itself.
  if (!std::isfinite(best.rss) || best.x.size() != static_cast<long>(f.size()))
    throw std::runtime_error("diagnose: no start of the fit gave a finite residual (a non-finite measurement or "
                             "prediction reached the fit)");
  return best;
}

/// Step 2, covariance: standard deviations (p, scaled) from σ̂² (JᵀJ)⁻¹ with σ̂² = sigma2 (µm²). A ridge relative to
/// the trace keeps directions the data cannot see at huge variance instead of a false zero.
Eigen::VectorXd linearised_sd(const LmResult& best, double sigma2, double ridge) {
  Eigen::MatrixXd A = best.JtJ; // p × p
  A.diagonal().array() += ridge * std::max(1.0, A.trace());
  const Eigen::MatrixXd cov = sigma2 * A.inverse(); // p × p
  return cov.diagonal().cwiseMax(0.0).cwiseSqrt();
}

/// Correlation (p × p) of the linearised covariance (JᵀJ + ridge)⁻¹: what a joint draw of the parameters needs beside
/// their (possibly widened) standard deviations.
Eigen::MatrixXd linearised_correlation(const LmResult& best, double ridge) {
  Eigen::MatrixXd A = best.JtJ; // p × p
  A.diagonal().array() += ridge * std::max(1.0, A.trace());
  const Eigen::MatrixXd cov = A.inverse();
  const Eigen::VectorXd d = cov.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  return d.asDiagonal() * cov * d.asDiagonal();
}

/// Step 2b, profile-likelihood walk. Nonlinear parameters (those with start lists, e.g. a time constant) make the
/// linearised covariance optimistic: the likelihood is not Gaussian in them. Walks each along its profile, on both
/// sides, until the RSS has risen by σ̂² (the 1σ profile-likelihood bound; the step starts at the linearised σ and
/// doubles, `profile_walk_steps` steps at most), refits the others there, and widens every uncertainty in sd (p,
/// scaled) to cover how far the refit moved.
void widen_by_profile_likelihood(EffectFit& f, const LmResult& best, const Box& box, double sigma2,
                                 const DiagnoseOptions& o, Eigen::VectorXd& sd) {
  const long p = static_cast<long>(f.size());
  for (long j = 0; j < p; ++j) {
    if (f.spec(static_cast<size_t>(j)).starts.empty()) continue;
    for (double sign : {-1.0, 1.0}) {
      double step = std::max(sd(j), o.profile_min_step);
      for (int k = 0; k < o.profile_walk_steps; ++k, step *= 2.0) {
        Eigen::VectorXd lo_j = box.lo, hi_j = box.hi, x = best.x;
        x(j) = std::clamp(best.x(j) + sign * step, box.lo(j), box.hi(j));
        lo_j(j) = hi_j(j) = x(j);
        const LmResult r = f.minimise(x, lo_j, hi_j);
        const bool reached = r.rss - best.rss >= sigma2 || x(j) == box.lo(j) || x(j) == box.hi(j);
        if (reached || k == o.profile_walk_steps - 1) {
          sd = sd.cwiseMax((r.x - best.x).cwiseAbs());
          break;
        }
      }
    }
  }
}

/// Step 3: the candidate with its parameters (own units), uncertainties and scores.
Candidate to_candidate(EffectFit& f, const LmResult& best, const Eigen::VectorXd& sd, double rss0, double n) {
  f.set(best.x);
  Candidate c;
  c.effects = f.specs();
  for (size_t e = 0; e < f.effects().size(); ++e) {
    const auto& eff = *f.effects()[e];
    std::vector<FittedParameter> params;
    for (size_t k = 0; k < eff.parameters().size(); ++k) {
      const int j = f.free_index(e, k);
      const auto& spec = eff.parameters()[k];
      const double u = j >= 0 ? sd(j) * spec.typical : 0.0;
      params.push_back({spec.key, eff.value(k), u, j >= 0});
      if (j >= 0) {
        const double end = 1e-6 * (spec.hi - spec.lo), v = eff.value(k);
        const double plausible_width = (std::isnan(spec.plausible_hi) ? spec.hi : spec.plausible_hi) -
                                       (std::isnan(spec.plausible_lo) ? spec.lo : spec.plausible_lo);
        params.back().determined = !(v <= spec.lo + end || v >= spec.hi - end) && !(u > plausible_width);
      }
      if (j < 0 || c.rejection) continue;
      // Plausibility: a value the data demand beyond what a real machine shows is the optimiser absorbing a pattern
      // the effect does not make — not a measurement of the effect. "Demand": outside the plausible range by more than
      // 2σ. A value merely wandering there along a direction the data cannot see (a thermal amplitude trading against
      // its time constant on two teeth: huge σ) is not rejected; its uncertainty says how little is known.
      const double v = eff.value(k);
      const double outside = std::max(spec.plausible_lo - v, v - spec.plausible_hi); // > 0: outside (file units)
      if (outside > 2.0 * u) {
        const double at_end = 1e-6 * (spec.hi - spec.lo);
        c.rejection = Decision{Reason::implausible_value, std::string(eff.type()) + "." + spec.key, {},
                               {{"value", v}, {"sd", u}, {"plausible_lo", spec.plausible_lo},
                                {"plausible_hi", spec.plausible_hi},
                                {"at_end_of_range", v <= spec.lo + at_end || v >= spec.hi - at_end ? 1.0 : 0.0}}};
      }
    }
    c.parameters.push_back(params);
    c.explanations.emplace_back(eff.explanation());
  }
  const double p = static_cast<double>(f.size());
  c.rms_before_um = std::sqrt(rss0 / n);
  c.rms_after_um = std::sqrt(best.rss / n);
  c.explained_fraction = rss0 > 0.0 ? 1.0 - best.rss / rss0 : 0.0;
  c.delta_bic = n * std::log(std::max(best.rss, 1e-300) / std::max(rss0, 1e-300)) + p * std::log(n);
  return c;
}

} // namespace

double sum_of_squares(const std::vector<double>& r) {
  double s = 0.0;
  for (double v : r) s += v * v;
  return s;
}

std::size_t subsample_stride(std::size_t n, std::size_t most) {
  return most == 0 || n <= most ? 1 : (n + most - 1) / most;
}

Candidate fit_effects(const grinding::GrindingSetup& setup, const EffectContribution& at_points,
                      const std::vector<double>& r0, const std::vector<std::string>& types,
                      const std::map<std::string, std::vector<double>>& warm, const SetupTermModel& setup_terms,
                      const DiagnoseOptions& o, const FitSubsample* subsample) {
  EffectFit f(setup, at_points, r0, types, setup_terms, o.threads, o.project_linear, o.keep_going);
  const Box box = parameter_box(f);
  const std::vector<Eigen::VectorXd> starts = start_points(f, box, warm);
  LmResult best;
  if (subsample && starts.size() > 1) {
    // The starts on every k-th point (an iteration there costs 1/k of one on all points), then the best start's
    // solution polished on all points: a few iterations from next to the minimum. One start: no search to save.
    EffectFit coarse(setup, subsample->at, subsample->r0, types, subsample->terms, o.threads, o.project_linear,
                     o.keep_going);
    best = f.minimise(best_of_starts(coarse, starts, box, o.threads).x, box.lo, box.hi);
    if (!std::isfinite(best.rss))
      throw std::runtime_error("diagnose: the fit on all points gave a non-finite residual (a non-finite measurement or "
                               "prediction reached the fit)");
  } else {
    best = best_of_starts(f, starts, box, o.threads);
  }
  const double n = static_cast<double>(r0.size());
  const double dof = n - static_cast<double>(f.size()) - setup_terms.count();
  const double sigma2 = best.rss / std::max(1.0, dof); // σ̂² (µm²)
  Eigen::VectorXd sd = linearised_sd(best, sigma2, o.covariance_ridge);
  const Eigen::VectorXd sd_linear = sd; // scaled units
  widen_by_profile_likelihood(f, best, box, sigma2, o, sd);
  const Eigen::VectorXd r0v = Eigen::Map<const Eigen::VectorXd>(r0.data(), static_cast<Eigen::Index>(r0.size()));
  Candidate c = to_candidate(f, best, sd, setup_terms.remove(r0v).squaredNorm(), n);
  c.correlation = linearised_correlation(best, o.covariance_ridge);
  c.linearised_sd.resize(sd_linear.size());
  for (Eigen::Index j = 0; j < sd_linear.size(); ++j) c.linearised_sd(j) = sd_linear(j) * f.spec(static_cast<size_t>(j)).typical;
  return c;
}

} // namespace geartopo::diagnosis
