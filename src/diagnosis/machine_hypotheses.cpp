// geartopo diagnosis — explanations beyond the library (machine_hypotheses.hpp). Units: µm; sizes mm or rad inside.
#include "machine_hypotheses.hpp"

#include "geartopo/core/uncertain_value.hpp"
#include "geartopo/effects/registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace geartopo::diagnosis {
namespace {

using machine::ChangeLaw;

/// A hypothesis before its fit: what it is. Its first-order columns at the points (n × p, µm per unit of each
/// coefficient: mm or rad for a component change, µm for a wheel flank's slope and crowning) are built when needed
/// (Columns below) and not kept: 300 hypotheses × 10⁵ points would hold half a gigabyte.
struct Hypothesis {
  Candidate c;         ///< changes (size 1, its law and τ), or one effect (wheel_flank_profile on one side, qualifier;
                       ///< wheel_profile_wear) whose linear parameters are fitted
  int component = -1;  ///< its component (−1: an effect)
  std::vector<int> fitted; ///< an effect: the indices of its parameters fitted (its columns), the others at default
};

struct LinearFit {
  bool ok = false;
  Eigen::VectorXd beta; ///< p
  Eigen::MatrixXd cov;  ///< p × p: σ̂² (X'ᵀX')⁻¹, σ̂² = RSS/ν of the whitened residual
  double rss = 0.0;
};

/// The columns with the set-up terms removed (and whitened, with stroke scatter): what they can explain.  // n × p
Eigen::MatrixXd projected(const Eigen::MatrixXd& X, const SetupTermModel& st) {
  Eigen::MatrixXd Xp(X.rows(), X.cols());
  for (Eigen::Index j = 0; j < X.cols(); ++j) Xp.col(j) = st.remove(Eigen::VectorXd(X.col(j)));
  return Xp;
}

LinearFit fit(const Eigen::MatrixXd& Xp, const Eigen::VectorXd& y, double setup_count) {
  LinearFit f;
  const auto n = static_cast<double>(y.size()), p = static_cast<double>(Xp.cols());
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Xp);
  // A direction the set-up terms already hold (a constant Z change is a turn of the helicoid) explains nothing new.
  if (qr.rank() < Xp.cols() || Xp.norm() == 0.0) return f;
  f.beta = qr.solve(y);
  f.rss = (y - Xp * f.beta).squaredNorm();
  const double sigma2 = f.rss / std::max(1.0, n - setup_count - p);
  f.cov = sigma2 * (Xp.transpose() * Xp).inverse();
  f.ok = f.beta.allFinite() && f.cov.allFinite();
  return f;
}

/// How much of A's columns lies in B's span (0 … 1, unit-free): ‖Q_Bᵀ A‖_F / ‖A‖_F.
double share_in_span(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(B);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(B.rows(), B.cols());
  const double a = A.norm();
  return a > 0.0 ? (Q.transpose() * A).norm() / a : 0.0;
}

std::string unit_of(machine::Quantity q) { return q == machine::Quantity::Length ? "µm" : "µrad"; }

/// A component's column (n, µm per unit) under a change's law: constant, × t, × (1 − e^(−t/τ)), or the pair
/// (× cos γ, × sin γ) once per revolution (n × 1 or n × 2). t: the points' grinding times (s), γ: their C angles (rad).
Eigen::MatrixXd law_columns(const Eigen::VectorXd& col, const machine::ComponentChange& ch, const Eigen::VectorXd& t,
                            const Eigen::VectorXd& gamma) {
  switch (ch.law) {
  case ChangeLaw::Constant: return col;
  case ChangeLaw::LinearInTime: return col.cwiseProduct(t);
  case ChangeLaw::SteadyState: return col.cwiseProduct(Eigen::VectorXd(1.0 - (-(t.array() / ch.time_constant_s)).exp()));
  case ChangeLaw::OncePerRevolution: {
    Eigen::MatrixXd X(col.size(), 2);
    X.col(0) = col.cwiseProduct(Eigen::VectorXd(gamma.array().cos()));
    X.col(1) = col.cwiseProduct(Eigen::VectorXd(gamma.array().sin()));
    return X;
  }
  }
  return col;
}

/// An effect's columns (n × k, µm per unit of each fitted parameter): the deviation of `spec` with fitted parameter
/// j set to 1 — every fitted parameter of a hypothesis' effect is linear (ParameterSpec::linear), zero at its default.
Eigen::MatrixXd effect_columns(const grinding::GrindingSetup& setup, const EffectContribution& at,
                               const scene::EffectSpec& spec, const std::vector<int>& fitted, int threads) {
  Eigen::MatrixXd X(static_cast<Eigen::Index>(at.size()), static_cast<Eigen::Index>(fitted.size()));
  for (size_t j = 0; j < fitted.size(); ++j) {
    std::vector<double> values = spec.values;
    for (const int k : fitted) values[static_cast<size_t>(k)] = 0.0;
    values[static_cast<size_t>(fitted[j])] = 1.0;
    const auto e = effects::make_effect(spec.type, values, setup);
    const effects::Effect* list[] = {e.get()};
    X.col(static_cast<Eigen::Index>(j)) = at.deviation_um(list, threads);
  }
  return X;
}

/// The parameters a hypothesis' effect fits: one wheel flank's slope and crowning (side from the qualifier), or the
/// wheel profile's wear rates.
std::vector<int> fitted_parameters_of(const Candidate& c) {
  if (c.effects.front().type == "wheel_profile_wear") return {0, 1};
  // wheel_flank_profile (slope, crowning) and wheel_flank_waviness (cos, sin): the two of the qualified side
  const int side = c.qualifier == "(left)" ? 0 : 1;
  return {2 * side, 2 * side + 1};
}

/// The points' grinding times (s) and C angles (rad), n each.
std::pair<Eigen::VectorXd, Eigen::VectorXd> times_and_angles(const EffectContribution& at) {
  const auto n = static_cast<Eigen::Index>(at.size());
  Eigen::VectorXd t(n), gamma(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    t(i) = at.path_point(static_cast<size_t>(i)).time_s;
    gamma(i) = at.path_point(static_cast<size_t>(i)).q.c;
  }
  return {t, gamma};
}

} // namespace

std::vector<Candidate> fit_machine_hypotheses(const grinding::GrindingSetup& setup, const EffectContribution& at,
                                              const std::vector<double>& residual_um, const SetupTermModel& st,
                                              const DiagnoseOptions& o, const std::vector<std::string>& in_scene) {
  const auto n = static_cast<Eigen::Index>(residual_um.size());
  const Eigen::VectorXd y = st.remove(Eigen::Map<const Eigen::VectorXd>(residual_um.data(), n));
  const double rss0 = y.squaredNorm(), ln_n = std::log(static_cast<double>(n));
  if (!(rss0 > 0.0) || n < 3) return {};

  // The job's duration: a drift's reach is judged over it (the last stroke's end, or the last point's time).
  const auto [t, gamma] = times_and_angles(at);
  double job_s = setup.path().strokes().empty() ? 0.0 : setup.path().strokes().back().t_end_s;
  job_s = std::max(job_s, t.maxCoeff());

  const Eigen::MatrixXd S = at.component_sensitivity_um(o.threads); // n × 43
  // The hypothesis' columns: its component's column times its law, or the wheel flank's slope and crowning columns.
  const auto columns_of = [&](const Hypothesis& h) -> Eigen::MatrixXd {
    if (h.component < 0) return effect_columns(setup, at, h.c.effects.front(), h.fitted, o.threads);
    return law_columns(S.col(h.component), h.c.changes.front(), t, gamma);
  };

  std::vector<Hypothesis> hyps;
  for (int k = 0; k < machine::kComponentCount; ++k) {
    if (S.col(k).isZero(0.0)) continue;
    const auto& info = machine::info(machine::component_at(k));
    const auto add = [&](ChangeLaw law, double tau = 0.0) {
      Hypothesis h;
      machine::ComponentChange ch;
      ch.component = info.id, ch.law = law, ch.time_constant_s = tau;
      h.c.changes.push_back(ch);
      h.component = k;
      hyps.push_back(std::move(h));
    };
    add(ChangeLaw::Constant);
    if (job_s > 0.0) {
      add(ChangeLaw::LinearInTime);
      // τ on a grid over the job: with one or two teeth measured a time constant is rarely determined, and a law
      // whose τ the data do not fix is reported as the linear drift it then looks like (below).
      for (double f : {0.125, 0.25, 0.5, 1.0, 2.0}) add(ChangeLaw::SteadyState, f * job_s);
    }
    if (info.axis == machine::Axis::C && info.position_dependent) add(ChangeLaw::OncePerRevolution);
  }
  // One wheel flank's profile error: the gear flanks it grinds, slope and crowning (µm), the other flank untouched.
  for (const int side : {0, 1}) {
    Hypothesis h;
    h.c.effects.push_back({"wheel_flank_profile", std::vector<double>(4, 0.0)});
    h.c.qualifier = side == 0 ? "(left)" : "(right)";
    h.fitted = fitted_parameters_of(h.c);
    hyps.push_back(std::move(h));
  }
  // One wheel flank's profile waviness: cos and sin parts at each wave count of a grid over the active profile (the
  // count is charged ln n like τ, and only the best count of a side is kept, below).
  for (const int side : {0, 1})
    for (const double cycles : {1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0}) {
      Hypothesis h;
      h.c.effects.push_back({"wheel_flank_waviness", {0.0, 0.0, 0.0, 0.0, cycles}});
      h.c.qualifier = side == 0 ? "(left)" : "(right)";
      h.fitted = fitted_parameters_of(h.c);
      hyps.push_back(std::move(h));
    }
  // The wheel's profile wearing with every stroke (its edge faster than its flanks): the profile slope and crowning
  // growing along the grinding order, not dressed during the gear.
  {
    Hypothesis h;
    h.c.effects.push_back({"wheel_profile_wear", {0.0, 0.0, 0.0}});
    h.fitted = fitted_parameters_of(h.c);
    hyps.push_back(std::move(h));
  }

  std::vector<Candidate> out;
  std::vector<const Hypothesis*> source; // parallel to out: what to rebuild the columns of
  // A hypothesis whose largest plausible size changes the projected data by less than 1e-4 µm RMS is invisible on
  // these flanks (a roll of the wheel spindle about its own axis turns a surface of revolution into itself): its fit
  // would be numerical noise with a huge value, so it is not tried.
  const double rms_scale = 1.0 / std::sqrt(static_cast<double>(n));
  const auto modelled = [&](const Hypothesis& h) {
    const std::string name = h.component >= 0 ? h.c.name() : h.c.effects.front().type;
    return std::find(in_scene.begin(), in_scene.end(), name) != in_scene.end();
  };
  for (auto& h : hyps) {
    if (modelled(h)) continue;
    const Eigen::MatrixXd X = columns_of(h);
    if (X.isZero(0.0)) continue;
    const Eigen::MatrixXd Xp = projected(X, st);
    double largest = 0.0;
    for (Eigen::Index j = 0; j < Xp.cols(); ++j) {
      double size_limit = 100.0; // µm: a wheel flank's slope or crowning
      if (h.component >= 0) {
        const auto& ch = h.c.changes.front();
        const bool length = machine::info(ch.component).quantity == machine::Quantity::Length;
        size_limit = length ? o.plausible_change_um * 1e-3 : o.plausible_change_urad * 1e-6;
        if (ch.law == ChangeLaw::LinearInTime && job_s > 0.0) size_limit /= job_s;
      }
      largest = std::max(largest, Xp.col(j).norm() * size_limit * rms_scale);
    }
    if (largest < 1e-4) continue;
    const LinearFit f = fit(Xp, y, st.count());
    if (!f.ok) continue;
    Candidate c = h.c;
    const auto p = static_cast<double>(Xp.cols());
    c.delta_bic = static_cast<double>(n) * std::log(std::max(f.rss, 1e-300) / rss0) + p * ln_n;
    c.explained_fraction = 1.0 - f.rss / rss0;
    c.rms_before_um = std::sqrt(rss0 / static_cast<double>(n));
    c.rms_after_um = std::sqrt(f.rss / static_cast<double>(n));
    c.correlation = f.cov.diagonal().cwiseSqrt().cwiseInverse().asDiagonal() * f.cov *
                    f.cov.diagonal().cwiseSqrt().cwiseInverse().asDiagonal();
    if (h.component >= 0) {
      auto& ch = c.changes.front();
      const auto q = machine::info(ch.component).quantity;
      const double limit = q == machine::Quantity::Length ? o.plausible_change_um * 1e-3 : o.plausible_change_urad * 1e-6;
      double sd = std::sqrt(f.cov(0, 0)), reach = 0.0, reach_sd = 0.0, phase_sd_deg = 0.0;
      if (ch.law == ChangeLaw::OncePerRevolution) {
        // a·cos(γ − φ) = a cos φ · cos γ + a sin φ · sin γ: a = |β|, φ = atan2(β₁, β₀); to first order
        // δa = gᵀδβ and δφ = hᵀδβ / a with g = (cos φ, sin φ), h = (−sin φ, cos φ).
        const double a = f.beta.norm();
        ch.size = a, ch.phase_rad = std::atan2(f.beta(1), f.beta(0));
        const Eigen::Vector2d g(std::cos(ch.phase_rad), std::sin(ch.phase_rad)), h(-g(1), g(0));
        sd = std::sqrt(g.dot(f.cov * g));
        phase_sd_deg = a > 0.0 ? std::sqrt(h.dot(f.cov * h)) / a * 180.0 / std::numbers::pi : 180.0;
        reach = a, reach_sd = sd;
      } else {
        ch.size = f.beta(0);
        const double per = ch.law == ChangeLaw::LinearInTime ? job_s : 1.0;
        reach = std::abs(ch.size) * per, reach_sd = sd * per;
      }
      c.change_sd.push_back(sd);
      const double scale = machine::file_per_internal(ch.law, q);
      // Its size as a parameter (file units), and the law's second one where it has one: the phase fitted, τ chosen
      // from the grid — each charged ln n in the ΔBIC like any fitted parameter.
      std::vector<FittedParameter> params{{machine::size_key(ch.law, q), ch.size * scale, sd * scale, true}};
      const double phase_deg = ch.phase_rad * 180.0 / std::numbers::pi;
      if (ch.law == ChangeLaw::OncePerRevolution) params.push_back({"phase_deg", phase_deg, phase_sd_deg, true});
      if (ch.law == ChangeLaw::SteadyState) {
        params.push_back({"time_constant_s", ch.time_constant_s, 0.0, true});
        c.delta_bic += ln_n;
      }
      c.parameters.push_back(std::move(params));
      std::string text = machine::describe(ch, text::with_uncertainty(ch.size * scale, sd * scale, true),
                                           ch.law == ChangeLaw::OncePerRevolution
                                               ? text::with_uncertainty(phase_deg, phase_sd_deg)
                                               : std::string());
      if (ch.law == ChangeLaw::LinearInTime)
        text += fmt::format(" ({:+.3g} {} over the {:.0f}-min job)", ch.size * job_s * (scale / 60.0), unit_of(q), job_s / 60.0);
      c.description = text;
      if (reach - 2.0 * reach_sd > limit)
        c.rejected = fmt::format("{} over the job is {:.3g} {}, beyond the {:g} {} a machine element plausibly changes",
                                 machine::info(ch.component).name, reach * (q == machine::Quantity::Length ? 1e3 : 1e6),
                                 unit_of(q), q == machine::Quantity::Length ? o.plausible_change_um : o.plausible_change_urad,
                                 unit_of(q));
    } else if (c.effects.front().type == "wheel_flank_waviness") {
      const bool left = c.qualifier == "(left)";
      auto& values = c.effects.front().values;
      values[left ? 0 : 2] = f.beta(0), values[left ? 1 : 3] = f.beta(1);
      const std::string side = left ? "left" : "right";
      // amplitude a = |β| and its σ to first order along β (as once per revolution)
      const double a = f.beta.norm();
      const Eigen::Vector2d g = a > 0.0 ? Eigen::Vector2d(f.beta / a) : Eigen::Vector2d(1.0, 0.0);
      const double a_sd = std::sqrt(g.dot(f.cov * g));
      // a·cos(2π n t − φ): φ = atan2(b, a_cos), its σ to first order across β (h ⟂ g), in degrees
      const Eigen::Vector2d h(-g(1), g(0));
      const double phase_deg = std::atan2(f.beta(1), f.beta(0)) * 180.0 / std::numbers::pi;
      const double phase_sd_deg = a > 0.0 ? std::sqrt(h.dot(f.cov * h)) / a * 180.0 / std::numbers::pi : 180.0;
      c.parameters.push_back({{side + "_cos_um", f.beta(0), std::sqrt(f.cov(0, 0)), true},
                              {side + "_sin_um", f.beta(1), std::sqrt(f.cov(1, 1)), true},
                              {"cycles", values[4], 0.0, true}});
      c.delta_bic += ln_n; // the wave count, chosen from the grid
      c.description = fmt::format("the wheel flank that grinds the {} flanks is wavy: amplitude {} µm, {:g} waves over "
                                  "the active profile, phase {}° at its root (the other wheel flank smooth)",
                                  side, text::with_uncertainty(a, a_sd), values[4],
                                  text::with_uncertainty(phase_deg, phase_sd_deg));
      if (a - 2.0 * a_sd > 20.0)
        c.rejected = fmt::format("a wave of {:.3g} µm is beyond the 20 µm a dressed wheel plausibly carries", a);
    } else if (c.effects.front().type == "wheel_profile_wear") {
      auto& values = c.effects.front().values;
      values[0] = f.beta(0), values[1] = f.beta(1);
      const double slope_sd = std::sqrt(f.cov(0, 0)), crowning_sd = std::sqrt(f.cov(1, 1));
      c.parameters.push_back({{"profile_slope_um_per_stroke", f.beta(0), slope_sd, true},
                              {"profile_crowning_um_per_stroke", f.beta(1), crowning_sd, true},
                              {"dressing_interval_strokes", 0.0, 0.0, false}});
      const double strokes = static_cast<double>(setup.path().strokes().size());
      c.description = fmt::format(
          "the wheel's profile wears with the strokes: the gear profile slope changes by {} µm and its crowning by {} "
          "µm per stroke ({} µm and {} µm over the {:.0f} strokes)",
          text::with_uncertainty(f.beta(0), slope_sd, true), text::with_uncertainty(f.beta(1), crowning_sd, true),
          text::with_uncertainty(f.beta(0) * strokes, slope_sd * strokes, true),
          text::with_uncertainty(f.beta(1) * strokes, crowning_sd * strokes, true), strokes);
      const auto specs = effects::make_effect("wheel_profile_wear")->parameters();
      for (int j = 0; j < 2; ++j) {
        const double v = f.beta(j), sd = std::sqrt(f.cov(j, j));
        const auto& spec = specs[static_cast<size_t>(j)];
        if (v - 2.0 * sd > spec.plausible_hi || v + 2.0 * sd < spec.plausible_lo)
          c.rejected = fmt::format("{} = {:.3g} µm is outside its plausible range [{:g}, {:g}]", spec.key, v,
                                   spec.plausible_lo, spec.plausible_hi);
      }
    } else {
      const bool left = c.qualifier == "(left)";
      auto& values = c.effects.front().values;
      values[left ? 0 : 2] = f.beta(0), values[left ? 1 : 3] = f.beta(1);
      const std::string side = left ? "left" : "right";
      c.parameters.push_back({{side + "_slope_um", f.beta(0), std::sqrt(f.cov(0, 0)), true},
                              {side + "_crowning_um", f.beta(1), std::sqrt(f.cov(1, 1)), true}});
      c.description = fmt::format("the wheel flank that grinds the {} flanks has a profile error: slope {} µm, crowning {} "
                                  "µm on those flanks (the other wheel flank none)",
                                  side, text::with_uncertainty(f.beta(0), std::sqrt(f.cov(0, 0)), true),
                                  text::with_uncertainty(f.beta(1), std::sqrt(f.cov(1, 1)), true));
      const auto specs = effects::make_effect("wheel_flank_profile")->parameters();
      for (int j = 0; j < 2; ++j) {
        const double v = f.beta(j), sd = std::sqrt(f.cov(j, j));
        const auto& spec = specs[static_cast<size_t>((left ? 0 : 2) + j)];
        if (v - 2.0 * sd > spec.plausible_hi || v + 2.0 * sd < spec.plausible_lo)
          c.rejected = fmt::format("{} = {:.3g} µm is outside its plausible range [{:g}, {:g}]", spec.key, v,
                                   spec.plausible_lo, spec.plausible_hi);
      }
    }
    c.explanations.push_back(c.description);
    out.push_back(std::move(c));
    source.push_back(&h);
  }

  // A steady state whose time constant the data do not fix is no finding: kept only where it beats the same
  // component's constant and linear laws by the threshold, and then only its best τ.
  std::vector<bool> keep(out.size(), true);
  for (size_t a = 0; a < out.size(); ++a) {
    if (out[a].changes.empty() || out[a].changes.front().law != ChangeLaw::SteadyState) continue;
    for (size_t b = 0; b < out.size() && keep[a]; ++b) {
      if (a == b || out[b].changes.empty() || out[b].changes.front().component != out[a].changes.front().component) continue;
      const ChangeLaw lb = out[b].changes.front().law;
      if (lb == ChangeLaw::SteadyState ? out[b].delta_bic < out[a].delta_bic
                                       : out[a].delta_bic > out[b].delta_bic - o.bic_threshold)
        keep[a] = false;
    }
  }
  // One wheel flank's waviness: only the best wave count of each side.
  for (size_t a = 0; a < out.size(); ++a) {
    if (out[a].effects.empty() || out[a].effects.front().type != "wheel_flank_waviness") continue;
    for (size_t b = 0; b < out.size() && keep[a]; ++b)
      if (b != a && !out[b].effects.empty() && out[b].effects.front().type == "wheel_flank_waviness" &&
          out[b].qualifier == out[a].qualifier && (out[b].delta_bic < out[a].delta_bic || (out[b].delta_bic == out[a].delta_bic && b < a)))
        keep[a] = false;
  }
  // A kept steady state's τ with its 1σ range on the grid: the τ of the same component whose fit is within
  // Δ(−2 ln L) = n ln(RSS_τ/RSS_best) ≤ 1 of the best (the same parameter count, so that is their ΔBIC difference).
  for (size_t a = 0; a < out.size(); ++a) {
    if (!keep[a] || out[a].changes.empty() || out[a].changes.front().law != ChangeLaw::SteadyState) continue;
    const double tau = out[a].changes.front().time_constant_s;
    double lo = tau, hi = tau;
    for (size_t b = 0; b < out.size(); ++b) {
      if (out[b].changes.empty() || out[b].changes.front().law != ChangeLaw::SteadyState ||
          out[b].changes.front().component != out[a].changes.front().component || out[b].delta_bic - out[a].delta_bic > 1.0)
        continue;
      lo = std::min(lo, out[b].changes.front().time_constant_s);
      hi = std::max(hi, out[b].changes.front().time_constant_s);
    }
    for (auto& p : out[a].parameters.front())
      if (p.key == "time_constant_s") p.uncertainty = 0.5 * (hi - lo);
    out[a].description += lo < hi ? fmt::format(" (1σ: {:.0f} … {:.0f} s, on a grid of 1/8 … 2 jobs)", lo, hi)
                                  : std::string(" (1σ: within the grid's factor 2 around it)");
  }
  std::vector<size_t> order;
  for (size_t a = 0; a < out.size(); ++a)
    if (keep[a]) order.push_back(a);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (out[a].rejected.empty() != out[b].rejected.empty()) return out[a].rejected.empty();
    return out[a].delta_bic < out[b].delta_bic;
  });
  if (order.empty()) return {};
  // The best one's equivalence class: those within the threshold whose fields are ≥ 95 % alike both ways.
  const size_t best = order.front();
  const Eigen::MatrixXd best_columns = projected(columns_of(*source[best]), st);
  for (size_t a : order) {
    if (a == best || !out[a].rejected.empty() || out[a].delta_bic >= out[best].delta_bic + o.bic_threshold) continue;
    const Eigen::MatrixXd other = projected(columns_of(*source[a]), st);
    const double alike = std::min(share_in_span(other, best_columns), share_in_span(best_columns, other));
    if (alike >= 0.95) out[best].equivalent.push_back(out[a].name());
  }
  std::vector<Candidate> ranked;
  for (size_t a : order) ranked.push_back(std::move(out[a]));
  return ranked;
}

bool is_machine_hypothesis(const Candidate& c) {
  if (c.changes.size() == 1 && c.effects.empty()) return true;
  if (!c.changes.empty() || c.effects.size() != 1) return false;
  const std::string& type = c.effects.front().type;
  return ((type == "wheel_flank_profile" || type == "wheel_flank_waviness") &&
          (c.qualifier == "(left)" || c.qualifier == "(right)")) ||
         (type == "wheel_profile_wear" && c.qualifier.empty());
}

HypothesisField hypothesis_field(const grinding::GrindingSetup& setup, const EffectContribution& at, const Candidate& c,
                                 int threads) {
  if (!is_machine_hypothesis(c)) throw std::invalid_argument("hypothesis_field: " + c.name() + " is no machine hypothesis");
  HypothesisField f;
  if (!c.changes.empty()) {
    const auto& ch = c.changes.front();
    const auto [t, gamma] = times_and_angles(at);
    const Eigen::MatrixXd S = at.component_sensitivity_um(threads); // n × 43
    f.X = law_columns(S.col(machine::index(ch.component)), ch, t, gamma);
    f.beta = ch.law == ChangeLaw::OncePerRevolution
                 ? Eigen::VectorXd(Eigen::Vector2d(ch.size * std::cos(ch.phase_rad), ch.size * std::sin(ch.phase_rad)))
                 : Eigen::VectorXd::Constant(1, ch.size);
  } else {
    const std::vector<int> fitted = fitted_parameters_of(c);
    const auto& v = c.effects.front().values;
    f.X = effect_columns(setup, at, c.effects.front(), fitted, threads);
    f.beta = Eigen::Vector2d(v[static_cast<size_t>(fitted[0])], v[static_cast<size_t>(fitted[1])]);
  }
  return f;
}

} // namespace geartopo::diagnosis
