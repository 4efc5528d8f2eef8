// The across-series laws, their fits, the choice between them and their predictions (drift_model.hpp).
#include "geartopo/series/drift_model.hpp"

#include "geartopo/core/minimize.hpp"
#include "geartopo/core/statistics.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace geartopo::series {
namespace {

// The time constants profiled: from 36 s to 1000 h, far beyond any shift at both ends, so that a best τ at either
// end says "the series does not fix τ" (a step at the start, or a straight line).
constexpr double kTauLoH = 0.01, kTauHiH = 1000.0;
constexpr int kTauGrid = 161;
constexpr double kSignificance = 0.01; // F-test level for keeping a law

bool has(const std::vector<Law>& laws, Law l) { return std::find(laws.begin(), laws.end(), l) != laws.end(); }

int correction_sets(const std::vector<GearState>& s) {
  int m = 0;
  for (const auto& g : s) m = std::max(m, g.correction_set);
  return m + 1;
}

/// The design of the linear part at a fixed τ: columns offset, [amplitude], [wear], [steps 1..m−1].
/// Shape: n × (1 + thermal + wear + (m − 1)).
Eigen::MatrixXd linear_columns(const std::vector<GearState>& s, const std::vector<Law>& laws, double tau_h, int sets) {
  const int n = static_cast<int>(s.size());
  const bool thermal = has(laws, Law::ThermalDrift), wear = has(laws, Law::WheelWear), step = has(laws, Law::CorrectionStep);
  const int cols = 1 + thermal + wear + (step ? sets - 1 : 0);
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, cols);
  for (int k = 0; k < n; ++k) {
    int c = 0;
    X(k, c++) = 1.0;
    if (thermal) X(k, c++) = 1.0 - std::exp(-s[k].time_h / tau_h);
    if (wear) X(k, c++) = s[k].strokes_since_dressing;
    if (step)
      for (int j = 1; j < sets; ++j) X(k, c++) = s[k].correction_set == j ? 1.0 : 0.0;
  }
  return X;
}

struct LinearSolution {
  Eigen::VectorXd beta;
  double rss = std::numeric_limits<double>::infinity();
  bool full_rank = false;
};

LinearSolution solve_linear(const Eigen::MatrixXd& X, const Eigen::VectorXd& y) {
  LinearSolution r;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  qr.setThreshold(1e-10);
  r.full_rank = qr.rank() == X.cols();
  if (!r.full_rank) return r;
  r.beta = qr.solve(y);
  r.rss = (y - X * r.beta).squaredNorm();
  return r;
}

/// τ minimising the RSS: the log grid, then Brent between the grid neighbours of the best point.
struct TauProfile {
  double tau_h = 1.0;
  bool at_bound = false;
};
TauProfile profile_tau(const std::vector<GearState>& s, const Eigen::VectorXd& y, const std::vector<Law>& laws, int sets) {
  const auto rss_at_log = [&](double log_tau) { return solve_linear(linear_columns(s, laws, std::exp(log_tau), sets), y).rss; };
  const double lo = std::log(kTauLoH), hi = std::log(kTauHiH), h = (hi - lo) / (kTauGrid - 1);
  int best = 0;
  double best_rss = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kTauGrid; ++i) {
    const double r = rss_at_log(lo + i * h);
    if (r < best_rss) best_rss = r, best = i;
  }
  TauProfile p;
  p.at_bound = best == 0 || best == kTauGrid - 1;
  if (p.at_bound) {
    p.tau_h = std::exp(lo + best * h);
    return p;
  }
  const Minimum m = minimize_brent(rss_at_log, lo + (best - 1) * h, lo + (best + 1) * h, 1e-6);
  p.tau_h = std::exp(m.value <= best_rss ? m.x : lo + best * h);
  return p;
}

std::vector<std::string> parameter_names(const std::vector<Law>& laws, int sets) {
  std::vector<std::string> names{"offset_um"};
  if (has(laws, Law::ThermalDrift)) names.insert(names.end(), {"thermal_amplitude_um", "time_constant_h"});
  if (has(laws, Law::WheelWear)) names.emplace_back("wear_um_per_stroke");
  if (has(laws, Law::CorrectionStep))
    for (int j = 1; j < sets; ++j) names.push_back(fmt::format("step_{}_um", j));
  return names;
}

/// ∂y/∂θ at a state, θ in parameter_names order (the thermal amplitude and τ adjacent).
Eigen::VectorXd gradient(const LawFit& f, const GearState& at) {
  const auto& p = f.parameters;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(p.size()));
  for (size_t i = 0; i < p.size(); ++i) {
    const std::string& n = p[i].name;
    if (n == "offset_um") g(i) = 1.0;
    else if (n == "thermal_amplitude_um") g(i) = 1.0 - std::exp(-at.time_h / p[i + 1].value);
    else if (n == "time_constant_h") {
      const double tau = p[i].value, a = p[i - 1].value;
      g(i) = -a * at.time_h / (tau * tau) * std::exp(-at.time_h / tau);
    } else if (n == "wear_um_per_stroke") g(i) = at.strokes_since_dressing;
    else if (n.rfind("step_", 0) == 0) g(i) = at.correction_set == std::stoi(n.substr(5)) ? 1.0 : 0.0;
  }
  return g;
}

double model_value(const LawFit& f, const GearState& at) {
  double y = 0.0;
  const auto& p = f.parameters;
  for (size_t i = 0; i < p.size(); ++i) {
    const std::string& n = p[i].name;
    if (n == "offset_um") y += p[i].value;
    else if (n == "thermal_amplitude_um") y += p[i].value * (1.0 - std::exp(-at.time_h / p[i + 1].value));
    else if (n == "wear_um_per_stroke") y += p[i].value * at.strokes_since_dressing;
    else if (n.rfind("step_", 0) == 0 && at.correction_set == std::stoi(n.substr(5))) y += p[i].value;
  }
  return y;
}

void mark_undetermined(LawFit& f, bool tau_at_bound) {
  for (size_t i = 0; i < f.parameters.size(); ++i) {
    auto& q = f.parameters[i];
    if (q.name == "time_constant_h" && (tau_at_bound || !(q.sigma < q.value))) {
      q.determined = false;
      q.why = tau_at_bound ? fmt::format("the best τ lies at the search bound ({} h): the series is too short or too "
                                         "sparse to fix it", q.value < 1.0 ? kTauLoH : kTauHiH)
                           : fmt::format("σ_τ {:.3g} h exceeds τ {:.3g} h", q.sigma, q.value);
      auto& a = f.parameters[i - 1];
      a.determined = false;
      a.why = "trades against the undetermined time constant";
    }
  }
}

} // namespace

std::string to_string(Law law) {
  switch (law) {
  case Law::ThermalDrift: return "thermal drift";
  case Law::WheelWear: return "wheel wear";
  case Law::CorrectionStep: return "correction step";
  }
  return "?";
}

double LawFit::time_constant_h() const {
  for (const auto& q : parameters)
    if (q.name == "time_constant_h") return q.value;
  return std::numeric_limits<double>::quiet_NaN();
}

std::string LawFit::name() const {
  if (laws.empty()) return "noise only";
  std::string s;
  for (const auto l : laws) s += (s.empty() ? "" : " + ") + to_string(l);
  return s;
}

std::optional<LawFit> fit_laws(const std::vector<GearState>& states, const std::vector<double>& y_um,
                               const std::vector<Law>& laws, double floor_um) {
  const int n = static_cast<int>(states.size()), sets = correction_sets(states);
  const Eigen::VectorXd y = Eigen::Map<const Eigen::VectorXd>(y_um.data(), n);
  const bool thermal = has(laws, Law::ThermalDrift);
  TauProfile tau;
  if (thermal) tau = profile_tau(states, y, laws, sets);
  const Eigen::MatrixXd X = linear_columns(states, laws, tau.tau_h, sets);
  const LinearSolution lin = solve_linear(X, y);
  LawFit f;
  f.laws = laws;
  f.n = n;
  f.p = static_cast<int>(X.cols()) + (thermal ? 1 : 0);
  if (!lin.full_rank || n - f.p < 1) return std::nullopt;
  const auto names = parameter_names(laws, sets);
  for (int i = 0, b = 0; i < static_cast<int>(names.size()); ++i) {
    FittedParameter q;
    q.name = names[i];
    q.value = q.name == "time_constant_h" ? tau.tau_h : lin.beta(b++);
    f.parameters.push_back(q);
  }
  f.rss = lin.rss;
  f.sigma_um = std::max(std::sqrt(lin.rss / (n - f.p)), floor_um);
  // The full Jacobian (τ included) at the fit; shape n × p.
  Eigen::MatrixXd J(n, f.p);
  for (int k = 0; k < n; ++k) J.row(k) = gradient(f, states[k]).transpose();
  Eigen::FullPivLU<Eigen::MatrixXd> lu(J.transpose() * J);
  if (!lu.isInvertible()) return std::nullopt;
  f.covariance = f.sigma_um * f.sigma_um * lu.inverse();
  for (int i = 0; i < f.p; ++i) f.parameters[i].sigma = std::sqrt(std::max(0.0, f.covariance(i, i)));
  mark_undetermined(f, tau.at_bound);
  f.bic = n * std::log(std::max(lin.rss / n, floor_um * floor_um)) + f.p * std::log(static_cast<double>(n));
  return f;
}

namespace {

/// Against `base`: F = (ΔRSS/Δp) / s², significant above the (1 %/m) quantile, m the laws tried at this step
/// (Bonferroni: a series of noise names a law in at most 1 % of cases, however many laws are tried).
void test_against(LawFit& f, const LawFit& base, int m) {
  const int dp = f.p - base.p, dof = f.n - f.p;
  f.f_statistic = std::max(0.0, base.rss - f.rss) / dp / (f.sigma_um * f.sigma_um);
  f.f_critical = fisher_f_upper_quantile(kSignificance / m, dp, dof);
  f.significant = f.f_statistic > f.f_critical;
}

/// The significant extensions of `base` by one law each, smallest BIC first (none: nullopt).
std::optional<LawFit> best_extension(const std::vector<GearState>& s, const std::vector<double>& y, const LawFit& base,
                                     const std::vector<Law>& testable, double floor_um, std::vector<LawFit>& tried) {
  std::optional<LawFit> best;
  const int m = static_cast<int>(std::count_if(testable.begin(), testable.end(), [&](Law l) { return !has(base.laws, l); }));
  for (const Law l : testable) {
    if (has(base.laws, l)) continue;
    auto laws = base.laws;
    laws.push_back(l);
    std::sort(laws.begin(), laws.end());
    auto f = fit_laws(s, y, laws, floor_um);
    if (!f) continue;
    test_against(*f, base, m);
    tried.push_back(*f);
    if (f->significant && (!best || f->bic < best->bic)) best = *f;
  }
  return best;
}

} // namespace

SeriesFit fit_series(const std::vector<GearState>& states, const std::vector<double>& y_um, double floor_um) {
  if (states.size() != y_um.size()) throw std::invalid_argument("fit_series: states and values differ in number");
  if (states.size() < 3) throw std::invalid_argument("fit_series: fewer than 3 gears");
  if (!(floor_um > 0.0)) throw std::invalid_argument("fit_series: the scatter floor must be > 0");
  for (double v : y_um)
    if (!std::isfinite(v)) throw std::invalid_argument("fit_series: a value is not finite");
  SeriesFit r;
  std::vector<Law> testable;
  double t_min = states.front().time_h, t_max = t_min, s_min = states.front().strokes_since_dressing, s_max = s_min;
  for (const auto& g : states) {
    t_min = std::min(t_min, g.time_h), t_max = std::max(t_max, g.time_h);
    s_min = std::min(s_min, g.strokes_since_dressing), s_max = std::max(s_max, g.strokes_since_dressing);
  }
  if (states.size() >= 4 && t_max > t_min) testable.push_back(Law::ThermalDrift);
  else r.notes.push_back(fmt::format("{}: not testable ({})", to_string(Law::ThermalDrift),
                                      "fewer than 4 gears or no spread in time"));
  if (s_max > s_min) testable.push_back(Law::WheelWear);
  else r.notes.push_back(fmt::format("{}: not testable ({})", to_string(Law::WheelWear),
                                      "the strokes since dressing do not vary over the series"));
  if (correction_sets(states) > 1) testable.push_back(Law::CorrectionStep);
  else r.notes.push_back(fmt::format("{}: not testable ({})", to_string(Law::CorrectionStep),
                                      "the corrections never changed"));
  auto noise = fit_laws(states, y_um, {}, floor_um);
  r.chosen = *noise; // a constant always fits 3 or more gears
  r.tried.push_back(*noise);
  if (auto one = best_extension(states, y_um, r.chosen, testable, floor_um, r.tried)) {
    r.chosen = *one;
    if (auto two = best_extension(states, y_um, r.chosen, testable, floor_um, r.tried)) r.chosen = *two;
  }
  return r;
}

Predicted predict(const LawFit& fit, const GearState& at) {
  Predicted p;
  p.median_um = model_value(fit, at);
  const Eigen::VectorXd g = gradient(fit, at);
  p.sigma_um = std::sqrt(fit.sigma_um * fit.sigma_um + g.dot(fit.covariance * g));
  const double t = std::sqrt(fisher_f_upper_quantile(0.05, 1.0, std::max(1, fit.n - fit.p)));
  p.lower95_um = p.median_um - t * p.sigma_um;
  p.upper95_um = p.median_um + t * p.sigma_um;
  return p;
}

ClassLoss class_loss(const LawFit& fit, const GearState& next, const GearState& step, double limit_um, int max_gears) {
  ClassLoss c;
  for (int j = 1; j <= max_gears; ++j) {
    GearState at = next;
    at.time_h += (j - 1) * step.time_h;
    at.strokes_since_dressing += (j - 1) * step.strokes_since_dressing;
    const Predicted p = predict(fit, at);
    const bool early = std::max(std::abs(p.lower95_um), std::abs(p.upper95_um)) > limit_um;
    const bool median = std::abs(p.median_um) > limit_um;
    const bool late = p.lower95_um > limit_um || p.upper95_um < -limit_um;
    const auto mark = [&](std::optional<int>& g, std::optional<double>& s, std::optional<double>& t) {
      if (g) return;
      g = j, s = at.strokes_since_dressing, t = at.time_h;
    };
    if (early) mark(c.gears_early, c.strokes_early, c.time_early_h);
    if (median) mark(c.gears_median, c.strokes_median, c.time_median_h);
    if (late) mark(c.gears_late, c.strokes_late, c.time_late_h);
    if (j == 1) c.already = median;
    if (c.gears_late) break;
  }
  return c;
}

} // namespace geartopo::series
