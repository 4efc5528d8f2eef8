// geartopo diagnosis — tooth-to-tooth trends of the named patterns on one side (tooth_trends.hpp,
// docs/residual-patterns.md section 2). Units: µm, µm per tooth, rad.
#include "geartopo/diagnosis/residuals/tooth_trends.hpp"

#include "geartopo/core/statistics.hpp"
#include "residuals/residual_fit.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace geartopo::diagnosis {

using namespace residuals;

namespace {

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

namespace {

constexpr std::string_view kWhat = "tooth trend fit";
constexpr double kSmallestStandardErrorUm = 1e-100;

/// The flanks' indices by tooth, after the checks every fit needs: one side, teeth in 1..z and given once, finite
/// pattern values with standard errors > 0.
std::vector<std::size_t> checked_order(std::span<const FlankPatterns> flanks, int teeth_in_gear, const TrendOptions& o) {
  if (teeth_in_gear < 2) refuse(kWhat, fmt::format("{} teeth in the gear (at least 2)", teeth_in_gear));
  if (flanks.size() < 2) refuse(kWhat, fmt::format("{} flank(s); trends need at least 2 teeth", flanks.size()));
  if (!(o.significance_sigmas > 0.0 && std::isfinite(o.significance_sigmas)))
    refuse(kWhat, fmt::format("significance {} σ (must be finite and > 0)", o.significance_sigmas));
  const Flank side = flanks.front().side;
  std::vector<std::size_t> order(flanks.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  for (const auto& f : flanks) {
    if (f.side != side)
      refuse(kWhat, fmt::format("flanks of both sides given (tooth {} is {}, tooth {} is {}); trends are per side",
                                flanks.front().tooth, to_string(side), f.tooth, to_string(f.side)));
    if (f.tooth < 1 || f.tooth > teeth_in_gear)
      refuse(kWhat, fmt::format("tooth {} outside 1..{}", f.tooth, teeth_in_gear));
    for (NamedPattern p : kNamedPatterns) {
      const Estimate e = pattern_value(f, p);
      // The weights are 1/σ²: a σ below 1e-100 µm (no measurement has one) would overflow them.
      if (!std::isfinite(e.value) || !std::isfinite(e.standard_error) || !(e.standard_error > kSmallestStandardErrorUm))
        refuse(kWhat, fmt::format("tooth {}: {} = {} ± {} µm (needs a finite value and a standard error > {:g} µm)",
                                  f.tooth, to_string(p), e.value, e.standard_error, kSmallestStandardErrorUm));
    }
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return flanks[a].tooth < flanks[b].tooth; });
  for (std::size_t i = 1; i < order.size(); ++i)
    if (flanks[order[i]].tooth == flanks[order[i - 1]].tooth)
      refuse(kWhat, fmt::format("tooth {} given twice", flanks[order[i]].tooth));
  return order;
}

/// One side's values of one pattern over its teeth (n each): value, standard error, tooth number, tooth angle.
struct PatternSeries {
  Eigen::VectorXd y, s, j, th;
};

/// The trend tests of one side (significance level k σ, its two-sided tail p0): the Birge ratio of a model with p
/// parameters, χ²/(n − p) when the teeth scatter more than their standard errors allow (then standard errors are
/// scaled by its root), else 1; and whether adding q parameters (removing dchi of χ²) to reach a model with p
/// parameters and χ² chi2 explains significantly more — against χ²_q when the model's scatter is consistent with the
/// standard errors, else against F(q, n − p) with the observed scatter (an F test).
struct TrendTests {
  Eigen::Index n;
  double p0;
  double birge(double chi2, Eigen::Index p) const { return n > p ? std::max(1.0, chi2 / static_cast<double>(n - p)) : 1.0; }
  bool significant(double dchi, int q, double chi2, Eigen::Index p) const {
    const double q_d = static_cast<double>(q);
    if (n > p && chi2 / static_cast<double>(n - p) > 1.0)
      return dchi / q_d / (chi2 / static_cast<double>(n - p)) > fisher_f_upper_quantile(p0, q_d, static_cast<double>(n - p));
    return dchi > chi_squared_upper_quantile(p0, q_d);
  }
};

/// Two teeth: their difference, significant or not.
void two_teeth_trend(PatternTrend& t, const PatternSeries& v, double k, Flank side, const std::string& mean_text) {
  const std::string pname(to_string(t.pattern));
  t.tooth_a = static_cast<int>(v.j(0));
  t.tooth_b = static_cast<int>(v.j(1));
  t.difference_um = {v.y(1) - v.y(0), std::hypot(v.s(0), v.s(1))};
  const bool sig = std::abs(t.difference_um.value) > k * t.difference_um.standard_error;
  t.kind = sig ? TrendKind::Difference : TrendKind::Constant;
  t.sentence = sig ? fmt::format("{}: differs by {} ± {:.2f} µm between tooth {} and tooth {} ({} flanks)", pname,
                                 signed_um(t.difference_um.value), t.difference_um.standard_error, t.tooth_a, t.tooth_b,
                                 to_string(side))
                   : fmt::format("{}: tooth {} and tooth {} agree within {:g} standard errors (difference {} ± {:.2f} µm, "
                                 "{} flanks), {}",
                                 pname, t.tooth_a, t.tooth_b, k, signed_um(t.difference_um.value),
                                 t.difference_um.standard_error, to_string(side), mean_text);
}

/// The sentence of a trend of three teeth or more.
std::string trend_sentence(const PatternTrend& t, const PatternSeries& v, const SideTrends& out,
                           const std::string& teeth_text, const std::string& mean_text) {
  const std::string pname(to_string(t.pattern));
  const std::string scatter = t.scatter_beyond_model ? ", plus tooth-to-tooth scatter beyond the standard errors" : "";
  switch (t.kind) {
  case TrendKind::Constant: return fmt::format("{}: constant over {}, {}", pname, teeth_text, mean_text);
  case TrendKind::Linear:
    return fmt::format("{}: linear trend {} ± {:.3f} µm per tooth over {} (teeth {}–{}), {}{}", pname,
                       signed_um(t.slope_um_per_tooth.value, 3), t.slope_um_per_tooth.standard_error, teeth_text,
                       out.teeth.front(), out.teeth.back(), mean_text, scatter);
  case TrendKind::OncePerRevolution:
    return fmt::format("{}: once per revolution over {}, amplitude {:.2f} ± {:.2f} µm, largest near tooth {:.1f} (tooth "
                       "angle {:.1f}°), {}{}",
                       pname, teeth_text, t.amplitude_um.value, t.amplitude_um.standard_error, t.max_at_tooth,
                       t.phase_rad.value * 180.0 / std::numbers::pi, mean_text, scatter);
  case TrendKind::Irregular: {
    const auto n = static_cast<double>(v.y.size());
    const double sd = std::sqrt((v.y.array() - v.y.mean()).square().sum() / (n - 1.0));
    return fmt::format("{}: varies from tooth to tooth over {} (standard deviation {:.2f} µm) beyond the standard "
                       "errors, without a linear or once-per-revolution trend; {}",
                       pname, teeth_text, sd, mean_text);
  }
  case TrendKind::Difference: break; // two teeth only: two_teeth_trend
  }
  return {};
}

/// Three teeth or more: constant, linear in tooth number, once per revolution — the simplest that explains
/// significantly — or irregular.
void many_teeth_trend(PatternTrend& t, const PatternSeries& v, const TrendTests& tests, double chi2_constant,
                      int teeth_in_gear) {
  const Eigen::Index n = tests.n;
  // Linear in tooth number (centred for conditioning).
  Eigen::MatrixXd XL(n, 2);
  XL.col(0).setOnes();
  XL.col(1) = v.j.array() - v.j.mean();
  const auto lin = weighted_fit(XL, v.y, v.s); // distinct teeth: full rank unless the weights overflow
  if (!lin) refuse(kWhat, fmt::format("the linear trend of {} is not determined (weights out of range)", to_string(t.pattern)));
  t.slope_um_per_tooth = {lin->coef(1), std::sqrt(lin->cov(1, 1) * tests.birge(lin->chi2, 2))};
  t.linear_significant = tests.significant(chi2_constant - lin->chi2, 1, lin->chi2, 2);
  // Once per revolution.
  Eigen::MatrixXd XS(n, 3);
  XS.col(0).setOnes();
  XS.col(1) = v.th.array().cos();
  XS.col(2) = v.th.array().sin();
  const auto sin_fit = weighted_fit(XS, v.y, v.s);
  if (sin_fit) {
    t.sinusoid_fitted = true;
    amplitude_phase(sin_fit->coef(1), sin_fit->coef(2), sin_fit->cov.block<2, 2>(1, 1) * tests.birge(sin_fit->chi2, 3),
                    t.amplitude_um, t.phase_rad);
    t.max_at_tooth = 1.0 + t.phase_rad.value * teeth_in_gear / kTwoPi;
    t.sinusoid_significant = tests.significant(chi2_constant - sin_fit->chi2, 2, sin_fit->chi2, 3);
  }
  double chi2_model = chi2_constant;
  Eigen::Index params = 1;
  if (t.linear_significant &&
      !(t.sinusoid_significant && tests.significant(lin->chi2 - sin_fit->chi2, 1, sin_fit->chi2, 3))) {
    t.kind = TrendKind::Linear; // the simpler model unless the sinusoid explains significantly more
    chi2_model = lin->chi2;
    params = 2;
  } else if (t.sinusoid_significant) {
    t.kind = TrendKind::OncePerRevolution;
    chi2_model = sin_fit->chi2;
    params = 3;
  } else {
    t.kind = chi2_constant > chi_squared_upper_quantile(tests.p0, static_cast<double>(n - 1)) ? TrendKind::Irregular
                                                                                             : TrendKind::Constant;
  }
  if (t.kind == TrendKind::Linear || t.kind == TrendKind::OncePerRevolution)
    t.scatter_beyond_model = n > params && chi2_model > chi_squared_upper_quantile(tests.p0, static_cast<double>(n - params));
}

} // namespace

SideTrends fit_tooth_trends(std::span<const FlankPatterns> flanks, int teeth_in_gear, const TrendOptions& o) {
  const std::vector<std::size_t> order = checked_order(flanks, teeth_in_gear, o);
  const Flank side = flanks.front().side;
  SideTrends out;
  out.side = side;
  out.teeth_in_gear = teeth_in_gear;
  for (std::size_t i : order) out.teeth.push_back(flanks[i].tooth);

  const double k = o.significance_sigmas;
  const auto n = static_cast<Eigen::Index>(order.size());
  const TrendTests tests{n, standard_normal_two_sided_tail(k)}; // erfc(k/√2): 0.27 % at k = 3
  const std::string teeth_text = fmt::format("{} {} flanks", order.size(), to_string(side));
  for (std::size_t q = 0; q < kNamedPatterns.size(); ++q) {
    PatternTrend& t = out.trends[q];
    t.pattern = kNamedPatterns[q];
    t.teeth = order.size();
    PatternSeries v{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n)};
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto& f = flanks[order[static_cast<std::size_t>(i)]];
      const Estimate e = pattern_value(f, t.pattern);
      v.y(i) = e.value, v.s(i) = e.standard_error, v.j(i) = f.tooth;
      v.th(i) = kTwoPi * (f.tooth - 1) / teeth_in_gear;
    }
    const auto c0 = weighted_fit(Eigen::MatrixXd::Ones(n, 1), v.y, v.s);
    if (!c0) refuse(kWhat, fmt::format("the mean of {} is not determined (weights out of range)", to_string(t.pattern)));
    t.mean_um = {c0->coef(0), std::sqrt(c0->cov(0, 0) * tests.birge(c0->chi2, 1))};
    t.chi2_constant = c0->chi2;
    const std::string mean_text = fmt::format("mean {} ± {:.2f} µm", signed_um(t.mean_um.value), t.mean_um.standard_error);
    if (n == 2) {
      two_teeth_trend(t, v, k, side, mean_text);
      continue;
    }
    many_teeth_trend(t, v, tests, c0->chi2, teeth_in_gear);
    t.sentence = trend_sentence(t, v, out, teeth_text, mean_text);
  }
  return out;
}
} // namespace geartopo::diagnosis
