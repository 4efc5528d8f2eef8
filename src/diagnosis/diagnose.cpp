#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/residuals/line_noise.hpp"

#include "diagnosis_dump.hpp"
#include "effect_fit.hpp"
#include "machine_hypotheses.hpp"
#include "setup_terms.hpp"

#include "geartopo/core/flank.hpp"
#include "geartopo/core/statistics.hpp"
#include "geartopo/core/uncertain_value.hpp"
#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/residuals/flank_patterns.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/diagnosis/stroke_scatter.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/effects/registry.hpp" // effect_types
#include "geartopo/workbench/workbench.hpp"

#include <span>
#include <Eigen/Dense>
#include <fmt/format.h>
#include <fmt/ranges.h>

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
  if (!(o.unexplained_false_alarm > 0.0 && o.unexplained_false_alarm < 1.0))
    refuse("unexplained_false_alarm", o.unexplained_false_alarm, "in (0, 1)");
  if (o.pair_candidates < 1) refuse("pair_candidates", static_cast<double>(o.pair_candidates), "≥ 1");
  if (!(std::isfinite(o.covariance_ridge) && o.covariance_ridge >= 0.0))
    refuse("covariance_ridge", o.covariance_ridge, "finite and ≥ 0");
  if (o.plan_profile_traces < 1 || o.plan_helix_traces < 1)
    refuse("plan_profile_traces / plan_helix_traces", std::min(o.plan_profile_traces, o.plan_helix_traces), "≥ 1");
  if (o.plan_trace_points < 2) refuse("plan_trace_points", o.plan_trace_points, "≥ 2");
  if (o.plan_rows < 1 || o.plan_cols < 1) refuse("plan_rows / plan_cols", std::min(o.plan_rows, o.plan_cols), "≥ 1");
  if (o.profile_walk_steps < 0) refuse("profile_walk_steps", o.profile_walk_steps, "≥ 0");
  if (!(std::isfinite(o.profile_min_step) && o.profile_min_step > 0.0))
    refuse("profile_min_step", o.profile_min_step, "finite and > 0");
  for (int a = 0; a < 5; ++a)
    if (!(std::isfinite(o.stroke_repeatability_sd(a)) && o.stroke_repeatability_sd(a) >= 0.0))
      refuse("stroke_repeatability_sd", o.stroke_repeatability_sd(a), "finite and ≥ 0 on every axis");
  if (!o.model_uncertainty_um.allFinite())
    throw std::invalid_argument("diagnose: option model_uncertainty_um has a non-finite value");
}

/// The recommendation in words: the teeth and grid to measure, the ΔBIC gap expected after both explanations are
/// refitted (each way), the best few teeth with where on them the difference is largest.
std::string plan_sentence(const MeasurementPlan& plan, std::size_t named, double target, bool nested = false) {
  if (plan.teeth.empty()) return "Every tooth is measured already; more rows or columns per flank would be needed.";
  std::string teeth;
  for (size_t k = 0; k < std::min(named, plan.teeth.size()); ++k) {
    const auto& t = plan.teeth[k];
    teeth += fmt::format("{}tooth {} ({:.1f}σ; largest {:.2f} µm on its {} flank, row {}, column {})", k ? ", " : "",
                         t.tooth, t.separation_sigma, t.max_difference_um, t.flank == Flank::Left ? "left" : "right",
                         t.row, t.col);
  }
  const auto best = [](const std::vector<double>& v) {
    return static_cast<int>(std::max_element(v.begin(), v.end()) - v.begin()) + 1;
  };
  const auto& r = plan.recommended;
  // One explanation inside the other: if the smaller is right the larger refits its data and trails by its extra
  // parameters' penalty only — and is then no rival, its partner no longer pointed to (diagnose, "Ambiguity").
  const std::string nested_note =
      nested ? " — a few, the penalty of the larger one's extra parameters, if the smaller one is right: then the "
               "partner is no longer pointed to"
             : "";
  return fmt::format("{} teeth {} with {}, both flanks ({} points): after both explanations are "
                     "refitted, the expected ΔBIC gap is {:.0f} if {} is right and {:.0f} if {} is ({}{:g} needed{}; "
                     "{:.1f}σ apart before the refit, in units of the {:.2f} µm noise). Largest differences: {}; the "
                     "profile row {} and face-width column {} of the {} × {} grid carry most of it.",
                     r.resolves ? "To decide, measure" : "No option tried is expected to decide; the closest: measure",
                     fmt::join(r.teeth, ","), what_to_measure(r), r.points, r.delta_bic_if_first, plan.first,
                     r.delta_bic_if_second, plan.second, r.resolves ? "≥ " : "< ", target, nested_note,
                     r.separation_before_refit_sigma, plan.noise_um, teeth, best(plan.row_separation_sigma),
                     best(plan.col_separation_sigma), plan.rows, plan.cols);
}

/// Whether another measurement would tell an equivalence class's members apart, from their plan: the teeth that
/// would, or that no tooth of this gear on the grids tried does (their fields are alike there too).
std::string equivalence_sentence(const MeasurementPlan& plan) {
  const auto& r = plan.recommended;
  if (plan.teeth.empty()) return "Every tooth is measured: no measurement on this gear separates them.";
  if (!r.resolves)
    return fmt::format("No measurement of the other teeth tried separates them either (at most {:.1f}σ apart on "
                       "teeth {} with {}; expected ΔBIC gap {:.0f} / {:.0f} after the refit): "
                       "their fields are alike on every flank of this gear.",
                       r.separation_before_refit_sigma, fmt::join(r.teeth, ","), what_to_measure(r), r.delta_bic_if_first,
                       r.delta_bic_if_second);
  return fmt::format("Measuring teeth {} with {} would separate them (expected ΔBIC gap {:.0f} "
                     "if {} is right, {:.0f} if {} is).",
                     fmt::join(r.teeth, ","), what_to_measure(r), r.delta_bic_if_first, plan.first, r.delta_bic_if_second,
                     plan.second);
}

/// The columns of a library explanation's fitted parameters at its fitted values (n × P, µm per file unit, set-up
/// terms removed): central differences of its first-order deviation, a step of 10⁻³ of the value or its typical size.
Eigen::MatrixXd library_columns(const grinding::GrindingSetup& setup, const EffectContribution& at,
                                const SetupTermModel& setup_terms, const Candidate& c, int threads) {
  const auto field = [&](const std::vector<scene::EffectSpec>& specs) {
    std::vector<std::unique_ptr<effects::Effect>> owned;
    std::vector<const effects::Effect*> list;
    for (const auto& e : specs) {
      owned.push_back(effects::make_effect(e.type, e.values, setup));
      list.push_back(owned.back().get());
    }
    return Eigen::VectorXd(at.deviation_um(list, threads));
  };
  std::vector<Eigen::VectorXd> cols;
  for (size_t e = 0; e < c.effects.size(); ++e) {
    const auto specs = effects::make_effect(c.effects[e].type)->parameters();
    for (size_t k = 0; k < specs.size() && k < c.effects[e].values.size(); ++k) {
      if (!specs[k].fitted) continue;
      const double step = 1e-3 * std::max(std::abs(c.effects[e].values[k]), specs[k].typical);
      auto plus = c.effects, minus = c.effects;
      plus[e].values[k] += step, minus[e].values[k] -= step;
      cols.push_back(setup_terms.remove(Eigen::VectorXd((field(plus) - field(minus)) / (2.0 * step))));
    }
  }
  Eigen::MatrixXd J(static_cast<Eigen::Index>(at.size()), static_cast<Eigen::Index>(cols.size()));
  for (size_t j = 0; j < cols.size(); ++j) J.col(static_cast<Eigen::Index>(j)) = cols[j];
  return J;
}

/// Why a combination's parts are no measurement of two effects: their fields (set-up terms removed, first order at
/// the points) cancel — one part is more than twice what both leave together, "its parts cancel: thermal_drift
/// (6.10 µm RMS) and wheel_wear (5.20 µm RMS) leave 1.40 µm RMS together" — two large effects of opposite sign standing
/// in for a field neither makes (an A-axis drift as a thermal X shrink and a wear). Empty for a single effect or parts
/// that add.
std::string parts_cancel(const grinding::GrindingSetup& setup, const EffectContribution& at, const SetupTermModel& setup_terms,
                         const Candidate& c, int threads) {
  if (c.effects.size() < 2) return {};
  std::vector<std::unique_ptr<effects::Effect>> owned;
  std::vector<const effects::Effect*> all;
  for (const auto& e : c.effects) {
    owned.push_back(effects::make_effect(e.type, e.values, setup));
    all.push_back(owned.back().get());
  }
  const double n = static_cast<double>(at.size());
  const auto rms = [&](std::span<const effects::Effect* const> list) {
    return setup_terms.remove(Eigen::VectorXd(at.deviation_um(list, threads))).norm() / std::sqrt(n);
  };
  const double together = rms(all);
  std::vector<double> parts;
  for (const effects::Effect* e : all) parts.push_back(rms(std::span<const effects::Effect* const>(&e, 1)));
  if (*std::max_element(parts.begin(), parts.end()) <= 2.0 * together) return {};
  std::string named;
  for (size_t e = 0; e < parts.size(); ++e)
    named += fmt::format("{}{} ({:.2f} µm RMS)", e == 0 ? "" : " and ", c.effects[e].type, parts[e]);
  return fmt::format("its parts cancel: {} leave {:.2f} µm RMS together", named, together);
}

/// The partners a joint fit with the best effect is worth although the evidence does not favour them alone: those the
/// joint fit linearised at the single fits points to — what the best one leaves (set-up terms removed) on the best's and
/// a partner's parameter columns (library_columns), one of the partner's parameters at least 2σ from zero (σ from the
/// noise and the columns). Two passes per parameter instead of a nonlinear pair fit, which on 210 000 trace points
/// costs seconds; a partner the linearised fit does not point to cannot be indicated by the pair's fit either.
std::vector<std::string> partners_pointed_to(const grinding::GrindingSetup& setup, const EffectContribution& at,
                                             const SetupTermModel& setup_terms, const std::vector<double>& residual_before_um,
                                             const Candidate& best, const std::vector<const Candidate*>& partners,
                                             double noise_um, int threads) {
  std::vector<std::string> pointed;
  if (partners.empty()) return pointed;
  std::vector<std::unique_ptr<effects::Effect>> owned;
  std::vector<const effects::Effect*> list;
  for (const auto& e : best.effects) {
    owned.push_back(effects::make_effect(e.type, e.values, setup));
    list.push_back(owned.back().get());
  }
  const Eigen::VectorXd before = Eigen::Map<const Eigen::VectorXd>(residual_before_um.data(),
                                                                   static_cast<Eigen::Index>(residual_before_um.size()));
  const Eigen::VectorXd left = setup_terms.remove(Eigen::VectorXd(before - at.deviation_um(list, threads))); // (n)
  const Eigen::MatrixXd Jb = library_columns(setup, at, setup_terms, best, threads);                          // (n × p_b)
  for (const Candidate* partner : partners) {
    const Eigen::MatrixXd Jp = library_columns(setup, at, setup_terms, *partner, threads); // (n × p_p)
    if (Jp.cols() == 0) continue;
    Eigen::MatrixXd J(left.size(), Jb.cols() + Jp.cols());
    J << Jb, Jp;
    const Eigen::MatrixXd cov = (J.transpose() * J).completeOrthogonalDecomposition().pseudoInverse(); // (p × p) / σ²
    const Eigen::VectorXd theta = cov * (J.transpose() * left);
    for (Eigen::Index k = Jb.cols(); k < J.cols(); ++k)
      if (cov(k, k) > 0.0 && std::abs(theta(k)) >= 2.0 * noise_um * std::sqrt(cov(k, k))) {
        pointed.push_back(partner->effects.front().type);
        break;
      }
  }
  return pointed;
}

/// How much of a field lies in the span of B's columns (0 … 1): ‖B·β‖ / ‖f‖ with β the least-squares fit of f by B
/// (the projection onto the span; never the n × n Q, which for 10⁵ points would need 80 GB).
double share_of_field_in_span(const Eigen::VectorXd& f, const Eigen::MatrixXd& B) {
  if (B.cols() == 0 || f.norm() == 0.0) return 0.0;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(B);
  return (B * qr.solve(f)).norm() / f.norm();
}

/// Whether the effect `bigger` adds to `smaller` (nested in it) is indicated but confounded: one of its fitted
/// parameters lies 2σ or more from zero, and one correlates with one of smaller's by |ρ| ≥ √¾ ≈ 0.866 (linearised
/// covariance: its variance at least 4× what it would be alone, the usual sign of collinearity). Then the pair's ΔBIC
/// cannot accept it — the smaller explanation takes its part (wheel wear on two teeth half a turn apart is a thickness
/// difference eccentricity makes too) — yet the data point to it: the pair is a rival, not a partner nobody asked for.
bool confounded_partner(const Candidate& bigger, const Candidate& smaller) {
  std::vector<bool> added; // per fitted parameter of `bigger`, effect by effect: does it belong to the added effect
  bool indicated = false;  // a parameter of the added effect at least 2σ from zero: the data point to it
  for (size_t e = 0; e < bigger.effects.size(); ++e) {
    const bool extra = std::none_of(smaller.effects.begin(), smaller.effects.end(),
                                    [&](const scene::EffectSpec& s) { return s.type == bigger.effects[e].type; });
    for (const auto& p : bigger.parameters[e])
      if (p.fitted) {
        added.push_back(extra);
        indicated = indicated || (extra && std::abs(p.value) >= 2.0 * p.uncertainty);
      }
  }
  const auto& r = bigger.correlation;
  if (!indicated || r.rows() != static_cast<Eigen::Index>(added.size())) return false;
  for (Eigen::Index i = 0; i < r.rows(); ++i)
    for (Eigen::Index j = 0; j < r.cols(); ++j)
      if (added[static_cast<size_t>(i)] && !added[static_cast<size_t>(j)] && std::abs(r(i, j)) >= std::sqrt(0.75)) return true;
  return false;
}

/// The first `shown` names joined by ", ", then how many more there are and where they are listed: a class of 49
/// equivalent components is a line, not a page.
std::string listed_briefly(const std::vector<std::string>& names, std::size_t shown) {
  if (names.size() <= shown) return fmt::format("{}", fmt::join(names, ", "));
  return fmt::format("{} and {} more (all in diagnosis.json, \"equivalent\")",
                     fmt::join(names.begin(), names.begin() + static_cast<long>(shown), ", "), names.size() - shown);
}

} // namespace

std::string Candidate::name() const {
  std::string s;
  for (const auto& e : effects) s += (s.empty() ? "" : " + ") + e.type;
  for (const auto& c : changes)
    s += fmt::format("{}{} {}", s.empty() ? "" : " + ", machine::info(c.component).name, machine::to_string(c.law));
  return qualifier.empty() ? s : s + " " + qualifier;
}

bool Candidate::nested_in(const Candidate& bigger) const {
  if (effects.size() >= bigger.effects.size()) return false;
  return std::all_of(effects.begin(), effects.end(), [&](const scene::EffectSpec& e) {
    return std::any_of(bigger.effects.begin(), bigger.effects.end(),
                       [&](const scene::EffectSpec& f) { return f.type == e.type; });
  });
}

int Candidate::fitted_parameters() const {
  int p = 0;
  for (const auto& params : parameters)
    for (const auto& q : params) p += q.fitted ? 1 : 0;
  return p;
}

namespace {

/// Per flank with at least 10 points: the point indices and the 6-term quadratic surface in (roll length, z), both
/// scaled to [−1, 1] (idx.size() × 6) — the basis of the noise estimate and of the structured-remainder test.
struct FlankSurface {
  std::vector<size_t> idx;
  Eigen::MatrixXd X;
};

std::vector<FlankSurface> flank_surfaces(const std::vector<MeasuredPoint>& pts) {
  std::map<std::pair<int, int>, std::vector<size_t>> flanks;
  for (size_t i = 0; i < pts.size(); ++i) flanks[{pts[i].tooth, static_cast<int>(pts[i].flank)}].push_back(i);
  std::vector<FlankSurface> out;
  for (auto& [key, idx] : flanks) {
    if (idx.size() < 10) continue;
    double xlo = 1e300, xhi = -1e300, zlo = 1e300, zhi = -1e300;
    for (size_t i : idx) {
      xlo = std::min(xlo, pts[i].roll_length_mm), xhi = std::max(xhi, pts[i].roll_length_mm);
      zlo = std::min(zlo, pts[i].z_mm), zhi = std::max(zhi, pts[i].z_mm);
    }
    Eigen::MatrixXd X(static_cast<long>(idx.size()), 6);
    for (size_t k = 0; k < idx.size(); ++k) {
      const auto& p = pts[idx[k]];
      const double u = xhi > xlo ? 2 * (p.roll_length_mm - xlo) / (xhi - xlo) - 1 : 0.0;
      const double w = zhi > zlo ? 2 * (p.z_mm - zlo) / (zhi - zlo) - 1 : 0.0;
      X.row(static_cast<long>(k)) << 1.0, u, w, u * w, u * u, w * w;
    }
    out.push_back({std::move(idx), std::move(X)});
  }
  return out;
}

/// Σ over flanks of the squared norm (µm²) of r's least-squares quadratic surface, and its degrees of freedom (6 per
/// flank). Divided by σ², a χ² when r is noise: smooth structure left on the flanks shows up far more strongly here than
/// in Σ r²/σ² over all points, whose many noise degrees of freedom dilute it.
std::pair<double, double> surface_sum_of_squares(const std::vector<FlankSurface>& surfaces, const Eigen::VectorXd& r) {
  double ss = 0.0, dof = 0.0;
  for (const auto& f : surfaces) {
    Eigen::VectorXd y(static_cast<long>(f.idx.size()));
    for (size_t k = 0; k < f.idx.size(); ++k) y(static_cast<long>(k)) = r(static_cast<Eigen::Index>(f.idx[k]));
    const Eigen::VectorXd fit = f.X * f.X.colPivHouseholderQr().solve(y);
    ss += fit.squaredNorm();
    dof += 6.0;
  }
  return {ss, dof};
}

/// What is left with an explanation (or none) and whether it is more than noise.
struct Remainder {
  Eigen::VectorXd raw;     ///< measured − model − explanation, as measured (n, µm)
  Eigen::VectorXd removed; ///< the same with the set-up terms removed, as shown (n, µm)
  Eigen::VectorXd judged;  ///< what the tests of "more than noise" see: the whitened remainder (white noise of σ if the
                           ///< scene's stroke scatter and the probe noise are all that is left; = removed without scatter)
  double dof = 1.0;        ///< degrees of freedom left (count)
  std::string excess;      ///< which χ² test says it is more than noise, with the numbers; empty: noise
};

/// Why an explanation is no measurement: "thermal_drift.time_constant_s = 1e+05 is at the end of its allowed range
/// [10, 1e+05]" for the first fitted value on the end of its box; empty when none is.
std::string at_the_end_of_its_range(const Candidate& c) {
  for (size_t e = 0; e < c.effects.size(); ++e) {
    const auto specs = effects::make_effect(c.effects[e].type)->parameters();
    for (size_t k = 0; k < specs.size(); ++k) {
      const double v = c.effects[e].values[k], end = 1e-6 * (specs[k].hi - specs[k].lo);
      if (specs[k].fitted && (v <= specs[k].lo + end || v >= specs[k].hi - end))
        return fmt::format("{}.{} = {:g} is at the end of its allowed range [{:g}, {:g}]: no measured value",
                           c.effects[e].type, specs[k].key, v, specs[k].lo, specs[k].hi);
    }
  }
  return {};
}

/// Why an explanation's single values are no measurement: one at the end of its allowed range
/// (at_the_end_of_its_range), or one the data do not determine (FittedParameter::determined: a thermal drift's growth
/// and time constant trading against each other); empty when every fitted value is measured.
std::string not_measured(const Candidate& c) {
  if (std::string at_end = at_the_end_of_its_range(c); !at_end.empty()) return at_end;
  for (size_t e = 0; e < c.effects.size(); ++e)
    for (const auto& p : c.parameters[e])
      if (p.fitted && !p.determined) return fmt::format("{}.{} is not determined by these data", c.effects[e].type, p.key);
  return {};
}

/// "x_growth_um = 9.1 ± 1.2, time_constant_s = 600 ± 90": the fitted values of a candidate with their 1σ, each rounded
/// to its uncertainty (GUM §7.2.6, text::with_uncertainty).
std::string parameters_text(const Candidate& c) {
  std::string s;
  for (size_t e = 0; e < c.effects.size(); ++e)
    for (const auto& p : c.parameters[e])
      if (p.fitted)
        s += fmt::format("{}{}{}{}", s.empty() ? "" : ", ", c.effects.size() > 1 ? c.effects[e].type + "." : std::string(),
                         p.key, p.determined ? " = " + text::with_uncertainty(p.value, p.uncertainty)
                                             : std::string(" not determined by these data"));
  return s;
}

/// What a thermal drift with an undetermined amplitude or time constant still fixes: its X and Z growth between t1 and
/// t2 (s). δ(t) = g·(1 − e^(−t/τ)), so Δ = g·(e^(−t1/τ) − e^(−t2/τ)); 1σ by the delta method from the linearised
/// covariance (Candidate::linearised_sd and correlation: the same linearisation, so the trade between g and τ, which
/// leaves Δ nearly unchanged, cancels). Empty for another effect or when its values are all determined.
std::vector<std::string> thermal_growth_determined(const Candidate& c, double t1_s, double t2_s) {
  std::vector<std::string> out;
  long slot = 0; // the effect's first fitted value among the candidate's fitted values
  for (size_t e = 0; e < c.effects.size(); ++e) {
    const auto& params = c.parameters[e];
    const auto fitted_index = [&](const std::string& key) -> long {
      long k = slot;
      for (const auto& p : params) {
        if (!p.fitted) continue;
        if (p.key == key) return k;
        ++k;
      }
      return -1;
    };
    const auto value_of = [&](const std::string& key) {
      for (const auto& p : params)
        if (p.key == key) return &p;
      return static_cast<const FittedParameter*>(nullptr);
    };
    const FittedParameter *x = value_of("x_growth_um"), *z = value_of("z_growth_um"), *tau = value_of("time_constant_s");
    const long it = fitted_index("time_constant_s");
    const bool usable = c.effects[e].type == "thermal_drift" && x && z && tau && it >= 0 && tau->value > 0.0 &&
                        c.linearised_sd.size() == c.correlation.rows() && c.correlation.rows() > it;
    if (usable && !(x->determined && z->determined && tau->determined)) {
      const double a = std::exp(-t1_s / tau->value), b = std::exp(-t2_s / tau->value);
      for (const FittedParameter* g : {x, z}) {
        const long ig = fitted_index(g->key);
        if (ig < 0 || ig >= c.correlation.rows()) continue;
        // Δ = g (a − b); ∂Δ/∂g = a − b, ∂Δ/∂τ = g (a t1 − b t2)/τ².
        const double delta = g->value * (a - b);
        const double dg = (a - b) * c.linearised_sd(ig);
        const double dt = g->value * (a * t1_s - b * t2_s) / (tau->value * tau->value) * c.linearised_sd(it);
        const double var = dg * dg + dt * dt + 2.0 * c.correlation(ig, it) * dg * dt;
        out.push_back(fmt::format("{} grew by {} µm between {:.1f} and {:.1f} min", g == x ? "X" : "Z",
                                  text::with_uncertainty(delta, std::sqrt(std::max(var, 0.0)), true), t1_s / 60.0,
                                  t2_s / 60.0));
      }
    }
    for (const auto& p : params) slot += p.fitted ? 1 : 0;
  }
  return out;
}

/// The pattern of a residual r (µm, set-up terms removed), one sentence: the two largest named patterns
/// (docs/residual-patterns.md) averaged over the measured flanks with their spread, and the RMS per tooth.
std::string residual_pattern_sentence(const grinding::GrindingSetup& setup, const std::vector<MeasuredPoint>& pts,
                                      const std::vector<double>& r, double noise_um) {
  PatternOptions po;
  po.noise_um = noise_um;
  std::vector<FlankPatterns> fitted;
  for (const auto& f : flank_residuals(setup.ranges(), pts, r)) {
    try {
      fitted.push_back(fit_flank_patterns(f, po));
    } catch (const std::invalid_argument&) { // too few distinct positions on this flank for the six patterns
    }
  }
  std::string text;
  if (!fitted.empty()) {
    struct Spread {
      NamedPattern pattern;
      double mean = 0.0, lo = 1e300, hi = -1e300;
    };
    std::vector<Spread> spreads;
    for (NamedPattern p : kNamedPatterns) {
      Spread s{p};
      for (const auto& f : fitted) {
        const double v = pattern_value(f, p).value;
        s.mean += v / static_cast<double>(fitted.size()), s.lo = std::min(s.lo, v), s.hi = std::max(s.hi, v);
      }
      spreads.push_back(s);
    }
    // Largest by how far the flanks reach, not the mean alone: a pattern growing from tooth to tooth averages small.
    const auto reach = [](const Spread& s) { return std::max(std::abs(s.lo), std::abs(s.hi)); };
    std::stable_sort(spreads.begin(), spreads.end(), [&](const Spread& a, const Spread& b) { return reach(a) > reach(b); });
    for (size_t k = 0; k < 2; ++k)
      text += fitted.size() > 1
                  ? fmt::format("{}{} {:+.2f} µm on average (from {:+.2f} to {:+.2f})", k ? " and " : "",
                                to_string(spreads[k].pattern), spreads[k].mean, spreads[k].lo, spreads[k].hi)
                  : fmt::format("{}{} {:+.2f} µm", k ? " and " : "", to_string(spreads[k].pattern), spreads[k].mean);
    text += fmt::format(" over the {} measured flank{}", fitted.size(), fitted.size() > 1 ? "s" : "");
  }
  std::map<int, std::pair<double, int>> per_tooth; // tooth → (Σ r², count)
  for (size_t i = 0; i < pts.size(); ++i) per_tooth[pts[i].tooth].first += r[i] * r[i], ++per_tooth[pts[i].tooth].second;
  std::string teeth;
  for (const auto& [tooth, ss] : per_tooth)
    teeth += fmt::format("{}{}: {:.2f}", teeth.empty() ? "" : ", ", tooth, std::sqrt(ss.first / ss.second));
  return text + (text.empty() ? "RMS" : "; RMS") + " by tooth " + teeth + " µm.";
}

} // namespace

namespace {

/// The set-up terms, with the stroke-to-stroke scatter the options declare (none: white noise, ordinary least squares).
SetupTermModel setup_term_model(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                                const std::vector<MeasuredPoint>& pts, double noise_um, const DiagnoseOptions& o) {
  if (o.stroke_repeatability_sd.isZero() && o.model_uncertainty_um.size() == 0) return SetupTermModel(setup.geometry(), pts);
  std::vector<int> space(pts.size());
  for (size_t i = 0; i < pts.size(); ++i)
    space[i] = grinding::space_of(pts[i].tooth, pts[i].flank, setup.geometry().teeth());
  const Eigen::MatrixXd G = stroke_sensitivity(setup, model, pts, o.stroke_repeatability_sd, o.threads); // n × 5
  return SetupTermModel(setup.geometry(), pts, StrokeScatter(space, G, noise_um, o.model_uncertainty_um));
}

} // namespace

double estimate_noise_um(const std::vector<MeasuredPoint>& pts, const std::vector<double>& r) {
  // Measured traces: σ from the lines' own point-to-point scatter (line_noise.hpp). A surface fitted across lines
  // would take their disagreement and every pattern the surface lacks for noise (issue 28: 1.23 µm on noise-free data).
  std::map<std::pair<int, int>, FlankResiduals> by_flank;
  for (size_t i = 0; i < pts.size(); ++i)
    by_flank[{pts[i].tooth, static_cast<int>(pts[i].flank)}].points.push_back({pts[i].roll_length_mm, pts[i].z_mm, r[i]});
  std::vector<FlankResiduals> flanks;
  for (auto& [key, f] : by_flank) flanks.push_back(std::move(f));
  if (const LineNoise lines = line_noise_um(flanks); lines.lines > 0) return std::max(lines.sigma_um, kNoiseFloorUm);
  double rss = 0.0, dof = 0.0;
  for (const auto& f : flank_surfaces(pts)) {
    Eigen::VectorXd y(static_cast<long>(f.idx.size()));
    for (size_t k = 0; k < f.idx.size(); ++k) y(static_cast<long>(k)) = r[f.idx[k]];
    const Eigen::VectorXd beta = f.X.colPivHouseholderQr().solve(y);
    rss += (y - f.X * beta).squaredNorm();
    dof += static_cast<double>(f.idx.size()) - 6.0;
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
  if (o.model_uncertainty_um.size() > 0 && o.model_uncertainty_um.rows() != static_cast<Eigen::Index>(pts.size()))
    throw std::invalid_argument(fmt::format("diagnose: option model_uncertainty_um has {} rows for {} measured points",
                                            o.model_uncertainty_um.rows(), pts.size()));
  Diagnosis d;
  d.points = static_cast<int>(pts.size());
  const auto base = predict(setup, model, pts, grinding::Method::Exact, o.threads);
  d.residual_before_um.resize(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) d.residual_before_um[i] = pts[i].deviation_um - base[i];
  const double n = static_cast<double>(pts.size());
  d.rms_before_um = std::sqrt(sum_of_squares(d.residual_before_um) / n);
  d.noise_estimated = o.noise_um <= 0.0;
  d.noise_um = d.noise_estimated ? estimate_noise_um(pts, d.residual_before_um) : o.noise_um;
  // Set-up terms (thickness offset, angular registration) are fitted in the baseline and in every candidate; with
  // declared stroke-to-stroke scatter by generalised least squares (the residual's covariance, stroke_scatter.hpp).
  const SetupTermModel setup_terms = setup_term_model(setup, model, pts, d.noise_um, o);
  const auto as_vector = [](const std::vector<double>& v) {
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
  };
  const Eigen::VectorXd before = as_vector(d.residual_before_um);
  d.rms_before_setup_um = std::sqrt(setup_terms.remove_shown(before).squaredNorm() / n);

  // Candidates: the ones asked for, or every library effect; never one the scene already models (fitting it again
  // would stack two copies and write a scene that lists it twice), never one twice.
  const bool asked = !o.candidates.empty();
  std::vector<std::string> types;
  for (const auto& t : asked ? o.candidates : effects::effect_types()) {
    // One wheel flank's profile error is a hypothesis beyond the library (machine_hypotheses.hpp), tried one flank at a
    // time when the library explains nothing; as a library candidate its four parameters would stand beside
    // wheel_profile's two for every symmetric dressing error.
    // So is the wheel's profile wearing with the strokes (wheel_profile_wear), which a wheel_wear + wheel_profile
    // pair would otherwise meet in every ranked table.
    // And one wheel flank's waviness (wheel_flank_waviness), tried over a grid of wave counts.
    if (!asked && (t == "wheel_flank_profile" || t == "wheel_profile_wear" || t == "wheel_flank_waviness")) continue;
    const bool modelled = std::find(in_scene.begin(), in_scene.end(), t) != in_scene.end();
    if (modelled && asked)
      throw std::invalid_argument(fmt::format("diagnose: candidate '{}' is already in the scene's effects", t));
    if (!modelled && std::find(types.begin(), types.end(), t) == types.end()) types.push_back(t);
  }

  // What every fit evaluates thousands of times: the effects' first-order deviation at these points, whose
  // parameter-independent part (pose, contact, axis Jacobian) is computed here once for all candidates.
  const EffectContribution at_points(setup, pts, o.threads);
  // On a large measurement the fits search from their starts on every k-th point (FitSubsample, effect_fit.hpp).
  std::optional<FitSubsample> subsample;
  if (const std::size_t k = subsample_stride(pts.size(), o.fit_search_points); k > 1) {
    std::vector<std::size_t> rows;
    for (std::size_t i = 0; i < pts.size(); i += k) rows.push_back(i);
    std::vector<MeasuredPoint> sub_pts;
    std::vector<double> sub_r0;
    DiagnoseOptions sub_o = o; // the model's uncertainty, if given, at the subsample's points
    const auto& M = o.model_uncertainty_um;
    if (M.size() > 0) sub_o.model_uncertainty_um.resize(static_cast<Eigen::Index>(rows.size()), M.cols());
    for (std::size_t j = 0; j < rows.size(); ++j) {
      sub_pts.push_back(pts[rows[j]]);
      sub_r0.push_back(d.residual_before_um[rows[j]]);
      if (M.size() > 0) sub_o.model_uncertainty_um.row(static_cast<Eigen::Index>(j)) = M.row(static_cast<Eigen::Index>(rows[j]));
    }
    subsample.emplace(FitSubsample{at_points.rows(rows), setup_term_model(setup, model, sub_pts, d.noise_um, sub_o),
                                   std::move(sub_r0)});
  }
  const FitSubsample* search = subsample ? &*subsample : nullptr;
  std::map<std::string, std::vector<double>> fitted_values;
  std::vector<Candidate> pairs; // every pair fitted, taken or not
  long long fits_done = 0, fits_known = static_cast<long long>(types.size());
  const auto candidate_fitted = [&] {
    if (o.on_candidate_fitted) o.on_candidate_fitted(++fits_done, fits_known);
  };
  for (const auto& t : types) {
    Candidate c = fit_effects(setup, at_points, d.residual_before_um, {t}, {}, setup_terms, o, search);
    c.significant = c.delta_bic < -o.bic_threshold && c.rejected.empty();
    fitted_values[t] = c.effects.front().values;
    d.ranked.push_back(std::move(c));
    candidate_fitted();
  }
  std::sort(d.ranked.begin(), d.ranked.end(), [](const Candidate& a, const Candidate& b) { return a.delta_bic < b.delta_bic; });

  // Rejected candidates (implausible parameters) go after the others, whatever their ΔBIC: the best explanation is
  // the first plausible significant one.
  std::stable_partition(d.ranked.begin(), d.ranked.end(), [](const Candidate& c) { return c.rejected.empty(); });
  if (!d.ranked.empty() && d.ranked.front().significant) {
    d.chosen = d.ranked.front();
    // Pairs by evidence, not by a gate on the residual: whenever two or more effects are significant alone, the best
    // is fitted jointly with each of the next ones (warm-started from the single fits), and a pair is taken when it
    // beats the best single effect by the ΔBIC threshold again. A few joint fits cost little beside the evidence a
    // fixed "residual > 1.5 σ" gate throws away (with hundreds of points 1.2 σ is already a highly significant excess).
    // Partners: every single effect the evidence favours (ΔBIC below −threshold), also one rejected alone — an effect
    // forced to mimic another's pattern on its own can take implausible values and be plausible beside it. The pair
    // faces the plausibility rule itself.
    std::vector<const Candidate*> favoured;
    for (const auto& c : d.ranked)
      if (c.delta_bic < -o.bic_threshold) favoured.push_back(&c);
    std::stable_sort(favoured.begin() + 1, favoured.end(),
                     [](const Candidate* a, const Candidate* b) { return a->delta_bic < b->delta_bic; });
    std::vector<std::string> top;
    for (const Candidate* c : favoured)
      if (top.size() < o.pair_candidates) top.push_back(c->effects.front().type);
    // Every pair among them, not only the best with the others: with few teeth one effect can stand in for the
    // partner of two others (thermal drift mimicking wear beside eccentricity on teeth 1, 2, 18, 35 — independent
    // hidden-effect tests), and the true pair then never gets fitted if the stand-in ranks first.
    // And the best with every other effect the linearised joint fit points to: a partner whose field the set-up terms
    // and the best one absorb on these teeth can be far from significant alone (wheel wear beside eccentricity on
    // teeth 1 and 18 with skip indexing: alone it is not favoured, and without it a thermal drift with no determined
    // value took its place).
    std::vector<std::pair<std::string, std::string>> pair_list;
    for (size_t a = 0; a < top.size(); ++a)
      for (size_t b = a + 1; b < top.size(); ++b) pair_list.emplace_back(top[a], top[b]);
    std::vector<const Candidate*> others;
    for (const auto& c : d.ranked)
      if (std::find(top.begin(), top.end(), c.effects.front().type) == top.end()) others.push_back(&c);
    for (const auto& t : partners_pointed_to(setup, at_points, setup_terms, d.residual_before_um, d.ranked.front(), others,
                                             d.noise_um, o.threads))
      pair_list.emplace_back(top.front(), t);
    fits_known += static_cast<long long>(pair_list.size());
    for (const auto& [first, second] : pair_list) {
      Candidate c = fit_effects(setup, at_points, d.residual_before_um, {first, second}, fitted_values, setup_terms, o,
                                search);
      c.significant = c.delta_bic < d.ranked.front().delta_bic - o.bic_threshold && c.rejected.empty();
      pairs.push_back(c);
      candidate_fitted();
      if (c.significant && (!d.combination || c.delta_bic < d.combination->delta_bic)) d.combination = c;
    }
    if (d.combination) d.chosen = d.combination;
  }

  // Ambiguity: a plausible explanation whose ΔBIC is within the threshold of the chosen one's is not told apart from it
  // by these data (the same rule that makes an effect significant against none). The verdict names both and the plan
  // says where they part.
  // A nested explanation (the chosen effect with one more, or the chosen pair's half) is a rival only when it is the
  // better fit without being better by the threshold: a worse superset is just the chosen one plus a partner the data do
  // not ask for, and the smaller half of a taken pair lost by the threshold already.
  if (d.chosen) {
    const auto nested = [&](const Candidate& c) { return c.nested_in(*d.chosen) || d.chosen->nested_in(c); };
    const auto rival = [&](const Candidate& c) {
      // Not significant alone is no reason to drop a rival: within the threshold of the chosen one, the data do not
      // prefer the chosen one either (thermal drift at ΔBIC −9.2 beside wheel wear at −12.2, on the truth scene's
      // thermal drift at 1.5 µm noise).
      if (!c.rejected.empty() || c.name() == d.chosen->name()) return false;
      if (nested(c))
        return c.effects.size() > d.chosen->effects.size() &&
               (c.delta_bic < d.chosen->delta_bic ||
                (c.delta_bic < d.chosen->delta_bic + o.bic_threshold && confounded_partner(c, *d.chosen)));
      // Another physics that loses only on BIC's parameter count is not told apart by these data either: when AIC
      // (the fit plus 2 per parameter, what the extra parameters buy on noise alone) does not prefer the chosen one,
      // the penalty is Occam's, not the measurement's (a true thermal drift at 1.5 µm noise on two teeth fits better
      // than wear, yet pays 2 ln n for a Z growth and a time constant they cannot fix).
      const double ln_n = std::log(static_cast<double>(pts.size()));
      const auto aic = [&](const Candidate& x) { return x.delta_bic - x.fitted_parameters() * (ln_n - 2.0); };
      return c.delta_bic < d.chosen->delta_bic + o.bic_threshold || aic(c) <= aic(*d.chosen);
    };
    for (const auto& c : d.ranked)
      if (rival(c)) d.rivals.push_back(c);
    for (const auto& c : pairs)
      if (rival(c)) d.rivals.push_back(c);
    std::stable_sort(d.rivals.begin(), d.rivals.end(),
                     [](const Candidate& a, const Candidate& b) { return a.delta_bic < b.delta_bic; });
    // The plan separates the chosen one from its best rival of other physics first; whether a partner comes with it
    // (a nested rival) is the second question, asked when no other rival is left.
    std::stable_partition(d.rivals.begin(), d.rivals.end(), [&](const Candidate& c) { return !nested(c); });
  }

  // What is left with an explanation (or none): by the exact simulation, with and without the set-up terms, and
  // whether it is more than noise. Two χ² tests, each at half the false-alarm probability: all of what is left, and its
  // smooth part per flank (a quadratic surface each), which a pattern the explanation does not make leaves behind even
  // when the total is near the noise (an A-axis drift mimicked by thermal drift + eccentricity left 1.12 σ RMS: the
  // total test missed it, the surfaces did not — independent hidden-effect tests).
  const auto surfaces = flank_surfaces(pts);
  const auto remainder = [&](const Candidate* c) {
    Remainder rem;
    rem.raw = before;
    if (c) {
      const auto effs = workbench::make_effects(c->effects, c->changes, setup);
      const effects::EffectsProcess with(model, effs);
      const auto after = predict(setup, with, pts, grinding::Method::Exact, o.threads);
      for (size_t i = 0; i < pts.size(); ++i) rem.raw(static_cast<Eigen::Index>(i)) = pts[i].deviation_um - after[i];
    }
    rem.removed = setup_terms.remove_shown(rem.raw);
    rem.judged = setup_terms.remove(rem.raw);
    rem.dof = std::max(1.0, n - setup_terms.count() - (c ? static_cast<double>(c->fitted_parameters()) : 0.0));
    const double s2 = d.noise_um * d.noise_um;
    const double chi2 = rem.judged.squaredNorm() / s2;
    const double limit = chi_squared_upper_quantile(0.5 * o.unexplained_false_alarm, rem.dof);
    const auto [surface_ss, surface_dof] = surface_sum_of_squares(surfaces, rem.judged);
    const double surface_limit =
        surface_dof > 0.0 ? chi_squared_upper_quantile(0.5 * o.unexplained_false_alarm, surface_dof) : 0.0;
    if (chi2 > limit)
      rem.excess = fmt::format("Σr²/σ² = {:.0f} > {:.0f}, the χ² limit for {:.0f} degrees of freedom at {:g}", chi2,
                               limit, rem.dof, 0.5 * o.unexplained_false_alarm);
    else if (surface_dof > 0.0 && surface_ss / s2 > surface_limit)
      rem.excess = fmt::format("its quadratic surface per flank: Σ/σ² = {:.0f} > {:.0f}, the χ² limit for {:.0f} "
                               "degrees of freedom at {:g}",
                               surface_ss / s2, surface_limit, surface_dof, 0.5 * o.unexplained_false_alarm);
    return rem;
  };
  Remainder rem = remainder(d.chosen ? &*d.chosen : nullptr);
  // Not an explanation, whatever its ΔBIC (issue 14): a remainder that is more than noise (the explanation does not
  // make the pattern; a "partly explained" culprit reads as the culprit). Then nothing is chosen: it becomes the
  // nearest, with why.
  if (d.chosen) {
    d.chosen->rms_after_um = std::sqrt(rem.removed.squaredNorm() / n);
    std::string why;
    if (!rem.excess.empty()) why = "what it leaves is more than noise (" + rem.excess + ")";
    if (!why.empty()) {
      // Said the same way everywhere it is listed: the ranked table and the combination no longer offer it.
      for (auto& c : d.ranked)
        if (c.name() == d.chosen->name()) c.rejected = why, c.significant = false;
      if (d.combination && d.combination->name() == d.chosen->name()) d.combination.reset();
      d.chosen->rejected = why;
      d.chosen->significant = false;
      d.nearest = d.chosen;
      d.nearest_rejected = why;
      d.chosen.reset();
      d.rivals.clear();
      d.plan.reset();
      rem = remainder(nullptr);
    }
  }
  if (!d.chosen && !d.nearest && !d.ranked.empty()) {
    const auto best = std::min_element(d.ranked.begin(), d.ranked.end(), [](const Candidate& a, const Candidate& b) {
      return a.delta_bic < b.delta_bic;
    });
    d.nearest = *best;
    d.nearest_rejected = !best->rejected.empty()
                             ? best->rejected
                             : fmt::format("not significant (ΔBIC {:.1f}, not below −{:g})", best->delta_bic, o.bic_threshold);
  }
  d.unexplained = !d.chosen && !rem.excess.empty();
  // Beyond the library (docs/diagnosis.md): when nothing in it explains the residual, the chain's own error components
  // under their laws and each wheel flank's profile. The best plausible, significant one that leaves noise is named
  // with its equivalence class; one that leaves more is the nearest machine element, and the residual stays unexplained.
  // Also when the library's explanation holds a value that is no measurement: at the end of its allowed range (a
  // thermal drift whose time constant runs away turns into a drift rate) or not determined by the data (a thermal drift
  // and a wear of opposite signs cancelling into the profile slope an A-axis drift makes), or a pair whose parts cancel
  // (parts_cancel: the same thermal drift and wear with values the data do fix). A machine element whose law
  // the data do determine is named instead when it fits better — by the threshold when the library's explanation can
  // leave the same field (an X axis approaching a steady state is a thermal X growth: the library's physics stays
  // named, with what the data fix of it); fitting worse within the threshold, with another field, it is a rival (a
  // C-axis radial motion beside a thermal drift whose time constant skip-indexed teeth do not fix).
  std::string hypothesis_rivals, nearest_element;
  std::string element_kept_out; // a machine element that fits about as well with the library explanation's own field
  std::optional<Candidate> equivalent_member; // the best other member of the chosen hypothesis' equivalence class
  std::string chosen_not_measured = d.chosen ? not_measured(*d.chosen) : std::string();
  if (d.chosen && chosen_not_measured.empty()) chosen_not_measured = parts_cancel(setup, at_points, setup_terms, *d.chosen, o.threads);
  if (d.unexplained || !chosen_not_measured.empty()) {
    d.hypotheses = fit_machine_hypotheses(setup, at_points, d.residual_before_um, setup_terms, o, in_scene);
    const bool usable = !d.hypotheses.empty() && d.hypotheses.front().rejected.empty() &&
                        d.hypotheses.front().delta_bic < -o.bic_threshold &&
                        (!d.chosen || d.hypotheses.front().delta_bic < d.chosen->delta_bic + o.bic_threshold);
    bool same_as_chosen = false;
    if (usable && d.chosen) {
      const HypothesisField hf = hypothesis_field(setup, at_points, d.hypotheses.front(), o.threads);
      const Eigen::VectorXd mine = setup_terms.remove(Eigen::VectorXd(hf.X * hf.beta));
      same_as_chosen = mine.norm() > 0.0 &&
                       share_of_field_in_span(mine, library_columns(setup, at_points, setup_terms, *d.chosen, o.threads)) >= 0.95;
    }
    // The same field: the element takes the place only when the data prefer it by the threshold (the library's
    // explanation then spends more parameters than the data determine on it: an A-axis drift as a thermal drift and a
    // wear cancelling each other).
    const bool element_first =
        usable && (!d.chosen || d.hypotheses.front().delta_bic < d.chosen->delta_bic - (same_as_chosen ? o.bic_threshold : 0.0));
    if (usable && same_as_chosen && !element_first)
      element_kept_out = fmt::format(
          " The best machine element, {} (ΔBIC {:.1f}), leaves a field {} can leave too, within {:g} of it: {} stays "
          "named.",
          d.hypotheses.front().description, d.hypotheses.front().delta_bic, d.chosen->name(), o.bic_threshold,
          d.chosen->name());
    if (usable && !same_as_chosen && !element_first) {
      Candidate& h = d.hypotheses.front();
      h.rms_after_um = std::sqrt(remainder(&h).removed.squaredNorm() / n);
      d.rivals.insert(d.rivals.begin(), h);
    }
    if (element_first) {
      Candidate& h = d.hypotheses.front();
      Remainder hr = remainder(&h);
      h.rms_after_um = std::sqrt(hr.removed.squaredNorm() / n);
      if (hr.excess.empty()) {
        if (d.chosen) { // the library's explanation at its bound becomes the nearest, with why
          d.nearest = d.chosen;
          d.nearest_rejected = chosen_not_measured;
          d.chosen.reset();
          d.rivals.clear();
        }
        h.significant = true;
        // The library's explanations that can leave the same field on these flanks: ≥ 95 % of the hypothesis' field
        // (set-up terms removed) lies in the span of the explanation's parameter columns at its fitted values.
        {
          const HypothesisField hf = hypothesis_field(setup, at_points, h, o.threads);
          const Eigen::VectorXd mine = setup_terms.remove(Eigen::VectorXd(hf.X * hf.beta));
          for (const auto& c : d.ranked)
            if (!c.effects.empty() && mine.norm() > 0.0 &&
                share_of_field_in_span(mine, library_columns(setup, at_points, setup_terms, c, o.threads)) >= 0.95)
              h.library_equivalent.push_back(c.name());
        }
        d.chosen = h;
        d.beyond_library = true;
        d.unexplained = false;
        rem = std::move(hr);
        // Within the threshold with a different field: rivals, as a library explanation's are (the verdict says
        // "ambiguous between", the plan what separates them). An equivalent one is not: one class, said as such.
        for (size_t k = 1; k < d.hypotheses.size(); ++k) {
          const Candidate& c = d.hypotheses[k];
          if (!c.rejected.empty() || c.delta_bic >= h.delta_bic + o.bic_threshold) continue;
          if (std::find(h.equivalent.begin(), h.equivalent.end(), c.name()) != h.equivalent.end()) {
            if (!equivalent_member) equivalent_member = c;
            continue;
          }
          hypothesis_rivals += (hypothesis_rivals.empty() ? "" : ", ") + fmt::format("{} (ΔBIC {:.1f})", c.name(), c.delta_bic);
          d.rivals.push_back(c);
        }
      } else if (d.unexplained) {
        h.rejected = "what it leaves is more than noise (" + hr.excess + ")";
        nearest_element = fmt::format(" Nearest machine element: {} (ΔBIC {:.1f}, leaving {:.2f} µm RMS) — {}.", h.description,
                                      h.delta_bic, h.rms_after_um, h.rejected);
      }
    }
    if (d.hypotheses.size() > o.hypotheses_listed) d.hypotheses.resize(o.hypotheses_listed);
  }
  // Nothing chosen because the best fit is no explanation: no single effect, which explains less, is one either.
  if (!d.chosen && d.nearest)
    for (auto& c : d.ranked)
      if (c.significant) {
        c.significant = false;
        c.rejected = fmt::format("explains less than {}, which is no explanation", d.nearest->name());
      }
  d.residual_after_um.assign(rem.removed.data(), rem.removed.data() + rem.removed.size());
  const double rms_after = std::sqrt(rem.removed.squaredNorm() / n);
  d.setup = setup_terms.fit(rem.raw, std::sqrt(rem.judged.squaredNorm() / rem.dof));
  d.chi2_after = rem.judged.squaredNorm() / (d.noise_um * d.noise_um);
  d.chi2_dof = rem.dof;
  if (d.unexplained) d.residual_pattern = residual_pattern_sentence(setup, pts, d.residual_after_um, d.noise_um);

  // Only now (the chosen one may have been no explanation): the plan that tells it from its best rival.
  // Every explanation with a field has one (library effects, pairs, machine hypotheses: measurement_plan.cpp).
  if (d.chosen && !d.rivals.empty())
    d.plan = plan_measurement(setup, pts, d.residual_before_um, *d.chosen, d.rivals.front(), d.noise_um, o);
  // An equivalence class is no ambiguity, but the user may ask whether another tooth would tell its members apart.
  if (d.chosen && d.beyond_library && equivalent_member)
    d.equivalent_plan = plan_measurement(setup, pts, d.residual_before_um, *d.chosen, *equivalent_member, d.noise_um, o);
  if (d.chosen && !d.rivals.empty())
    d.withheld = fmt::format("ambiguous between {} and {}: measure more (the plan) before adding either",
                             d.chosen->name(), d.rivals.front().name());
  // A value pushed against the end of its allowed range is no measurement (thermal drift's amplitude trading against
  // its time constant on two teeth): the effect explains the residual, but is not added with that value.
  else if (d.chosen)
    d.withheld = at_the_end_of_its_range(*d.chosen);
  // Set-up values assumed, not fitted: every unfitted parameter of what the verdict names (chosen, rivals, nearest).
  {
    std::vector<const Candidate*> named;
    if (d.chosen) named.push_back(&*d.chosen);
    for (const auto& r : d.rivals) named.push_back(&r);
    if (d.nearest) named.push_back(&*d.nearest);
    for (const Candidate* c : named)
      for (size_t e = 0; e < c->effects.size(); ++e)
        for (const auto& p : c->parameters[e]) {
          if (p.fitted) continue;
          const std::string line = fmt::format("{}.{} = {:g} (assumed: the effect's default; the scene gives none and "
                                               "the flanks cannot identify it)", c->effects[e].type, p.key, p.value);
          if (std::find(d.assumed.begin(), d.assumed.end(), line) == d.assumed.end()) d.assumed.push_back(line);
        }
  }
  const std::string setup_text =
      d.setup.rotation_identified
          ? fmt::format("Set-up (not process physics, fitted alongside): thickness {} µm, rotation {} µrad. ",
                        text::with_uncertainty(d.setup.thickness_um, d.setup.thickness_sd_um, true),
                        text::with_uncertainty(d.setup.rotation_urad, d.setup.rotation_sd_urad, true))
          : fmt::format("Set-up (not process physics, fitted alongside): offset {} µm (one flank side "
                        "measured: thickness and rotation not separable). ",
                        text::with_uncertainty(d.setup.thickness_um, d.setup.thickness_sd_um, true));
  const std::string nearest_text =
      d.nearest ? fmt::format("{} ({}; ΔBIC {:.1f}, leaving {:.2f} µm RMS) — rejected: {}", d.nearest->name(),
                              parameters_text(*d.nearest), d.nearest->delta_bic, d.nearest->rms_after_um,
                              d.nearest_rejected)
                : std::string("none fitted");
  if (d.chosen && d.beyond_library) {
    const Candidate& h = *d.chosen;
    d.verdict = setup_text +
                fmt::format("Not an effect of the library: {} (ΔBIC {:.1f}). ", h.description, h.delta_bic) +
                (h.library_equivalent.empty()
                     ? std::string()
                     : fmt::format("On these flanks the library's {} can leave the same field (≥ 95 % of it lies "
                                   "in what {} can do): the same deviation through another element. ",
                                   fmt::join(h.library_equivalent, ", "),
                                   h.library_equivalent.size() == 1 ? "that explanation" : "each of them")) +
                (h.equivalent.empty() ? std::string()
                                      : fmt::format("Equivalent on these flanks (the data cannot tell them apart; one "
                                                    "class): {}. {} ",
                                                    listed_briefly(h.equivalent, 8),
                                                    d.equivalent_plan ? equivalence_sentence(*d.equivalent_plan) : "")) +
                (hypothesis_rivals.empty()
                     ? std::string()
                     : fmt::format("Ambiguous between {} and {}, within ΔBIC {:g} with a different field: these data "
                                   "cannot tell them apart; not added to the scene. {} ",
                                   h.name(), hypothesis_rivals, o.bic_threshold,
                                   d.plan ? plan_sentence(*d.plan, o.plan_teeth_named, o.plan_target_delta_bic) : "")) +
                fmt::format("Adding it takes the residual (set-up removed) from {:.2f} to {:.2f} µm RMS (noise {:.2f} "
                            "µm{}). Nearest library explanation: {}.",
                            d.rms_before_setup_um, rms_after, d.noise_um, d.noise_estimated ? ", estimated" : "",
                            nearest_text);
  } else if (!d.chosen && d.unexplained) {
    d.verdict = setup_text +
                fmt::format("Unexplained: no effect of the library, alone or in a pair, explains the residual "
                            "({:.2f} µm RMS with the set-up removed, against {:.2f} µm noise: {}). What is left unexplained: "
                            "{} Nearest library explanation: {}.{} Nothing is added to the scene.",
                            d.rms_before_setup_um, d.noise_um, rem.excess, d.residual_pattern, nearest_text,
                            nearest_element);
  } else if (!d.chosen) {
    d.verdict = setup_text +
                fmt::format("No effect of the library is needed: with the set-up terms removed, the residual "
                            "({:.2f} µm RMS) is noise ({:.2f} µm{}). Nearest library explanation: {}.",
                            d.rms_before_setup_um, d.noise_um, d.noise_estimated ? ", estimated" : "", nearest_text);
  } else {
    std::string names = d.chosen->name();
    for (const auto& r : d.rivals) names += " and " + r.name();
    if (!d.rivals.empty())
      d.verdict = setup_text +
                  fmt::format("Ambiguous between {} (ΔBIC {:.1f} vs {:.1f}, within {:g}): these data cannot tell them "
                              "apart. {} ",
                              names, d.chosen->delta_bic, d.rivals.front().delta_bic, o.bic_threshold,
                              d.plan ? plan_sentence(*d.plan, o.plan_teeth_named, o.plan_target_delta_bic,
                                                     d.chosen->nested_in(d.rivals.front()) ||
                                                         d.rivals.front().nested_in(*d.chosen))
                                     : "");
    d.verdict += (d.rivals.empty() ? setup_text : std::string()) +
                 fmt::format("{}: {}. Adding it takes the residual (set-up removed) from {:.2f} to {:.2f} µm RMS "
                             "(noise {:.2f} µm{}).",
                             d.rivals.empty() ? "Missing" : "Best of them", d.chosen->name(), d.rms_before_setup_um,
                             rms_after, d.noise_um, d.noise_estimated ? ", estimated" : "");
  }
  // A fit the evidence favoured over what is named (chosen or nearest) but plausibility refused: said aloud, with why.
  const Candidate* named = d.chosen ? &*d.chosen : d.nearest ? &*d.nearest : nullptr;
  const auto better = std::min_element(d.ranked.begin(), d.ranked.end(), [](const Candidate& a, const Candidate& b) {
    return a.delta_bic < b.delta_bic;
  });
  if (named && better != d.ranked.end() && better->name() != named->name() && !better->rejected.empty() &&
      better->delta_bic < named->delta_bic)
    d.verdict += fmt::format(" {} fits better (ΔBIC {:.1f}) but was rejected: {}.", better->name(), better->delta_bic,
                             better->rejected);
  if (!d.withheld.empty() && d.rivals.empty()) d.verdict += " Not added to the scene: " + d.withheld + ".";
  // What the data fix when single values are "not determined" (a thermal drift's amplitude and time constant).
  if (d.chosen) {
    double t1 = 1e300, t2 = -1e300;
    for (size_t i = 0; i < pts.size(); ++i)
      t1 = std::min(t1, at_points.path_point(i).time_s), t2 = std::max(t2, at_points.path_point(i).time_s);
    d.determined = thermal_growth_determined(*d.chosen, t1, t2);
    if (!d.determined.empty())
      d.verdict += fmt::format(" Its single values are not all determined; the data fix: {}.", fmt::join(d.determined, "; "));
  }
  d.verdict += element_kept_out;
  if (!d.assumed.empty()) {
    std::string list;
    for (const auto& a : d.assumed) list += (list.empty() ? "" : "; ") + a;
    d.verdict += " Set-up values assumed, not measured: " + list + ".";
  }
  dump_if_asked(d);
  return d;
}

} // namespace geartopo::diagnosis
