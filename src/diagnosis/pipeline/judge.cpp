// geartopo diagnosis — stage 3 (stages.hpp): the library's pick judged against the noise, and what its values
// measure. Units: µm.
#include "stages.hpp"

#include "geartopo/core/statistics.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <algorithm>
#include <cmath>
#include <span>

namespace geartopo::diagnosis::stages {
namespace {

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

/// A combination's parts cancel when one part is more than twice what both leave together (set-up terms removed,
/// first order at the points): two large effects of opposite sign standing in for a field neither makes (an A-axis
/// drift as a thermal X shrink and a wear). None for a single effect or parts that add.
std::optional<Decision> parts_cancel(const Context& ctx, const Candidate& c) {
  if (c.effects.size() < 2) return std::nullopt;
  std::vector<std::unique_ptr<effects::Effect>> owned;
  std::vector<const effects::Effect*> all;
  for (const auto& e : c.effects) {
    owned.push_back(effects::make_effect(e.type, e.values, ctx.setup));
    all.push_back(owned.back().get());
  }
  const auto rms = [&](std::span<const effects::Effect* const> list) {
    return ctx.setup_terms.remove(Eigen::VectorXd(ctx.at_points.deviation_um(list, ctx.options.threads))).norm() /
           std::sqrt(ctx.n);
  };
  const double together = rms(all);
  std::vector<double> parts;
  for (const effects::Effect* e : all) parts.push_back(rms(std::span<const effects::Effect* const>(&e, 1)));
  if (*std::max_element(parts.begin(), parts.end()) <= 2.0 * together) return std::nullopt;
  Decision d{Reason::parts_cancel, c.name()};
  for (size_t e = 0; e < parts.size(); ++e) {
    d.names.push_back(c.effects[e].type);
    d.numbers.emplace_back("part_rms_um", parts[e]);
  }
  d.numbers.emplace_back("together_rms_um", together);
  return d;
}

/// Why the best fit is no explanation when nothing is picked: its own rejection, or not significant.
Decision why_not_picked(const Context& ctx, const Candidate& best) {
  if (best.rejection) return *best.rejection;
  return Decision{Reason::not_significant, best.name(), {},
                  {{"delta_bic", best.delta_bic}, {"threshold", ctx.options.bic_threshold}}};
}

} // namespace

Remainder remainder_with(const Context& ctx, const Candidate* c) {
  const auto& o = ctx.options;
  Remainder rem;
  rem.raw = ctx.before;
  if (c) {
    const auto effs =
        workbench::make_effects(c->effects, c->changes, ctx.setup, ctx.options.chain, ctx.options.datum_face_z_mm);
    const effects::EffectsProcess with(ctx.model, effs, ctx.options.chain, ctx.options.datum_face_z_mm);
    const auto after = predict(ctx.setup, with, ctx.points, grinding::Method::Exact, o.threads);
    for (size_t i = 0; i < ctx.points.size(); ++i)
      rem.raw(static_cast<Eigen::Index>(i)) = ctx.points[i].deviation_um - after[i];
  }
  rem.removed = ctx.setup_terms.remove_shown(rem.raw);
  rem.judged = ctx.setup_terms.remove(rem.raw);
  rem.dof = std::max(1.0, ctx.n - ctx.setup_terms.count() - (c ? static_cast<double>(c->fitted_parameters()) : 0.0));
  const double s2 = ctx.noise_um * ctx.noise_um, alpha = 0.5 * o.unexplained_false_alarm;
  const double chi2 = rem.judged.squaredNorm() / s2;
  const double limit = chi_squared_upper_quantile(alpha, rem.dof);
  const auto [surface_ss, surface_dof] = surface_sum_of_squares(ctx.surfaces, rem.judged);
  const double surface_limit = surface_dof > 0.0 ? chi_squared_upper_quantile(alpha, surface_dof) : 0.0;
  const auto excess = [&](const char* test, double statistic, double lim, double dof) {
    Decision d{Reason::more_than_noise, c ? c->name() : std::string("none")};
    d.test = test;
    d.numbers = {{"statistic", statistic}, {"limit", lim}, {"dof", dof}, {"false_alarm", alpha}};
    return d;
  };
  if (chi2 > limit)
    rem.excess = excess("total", chi2, limit, rem.dof);
  else if (surface_dof > 0.0 && surface_ss / s2 > surface_limit)
    rem.excess = excess("surface", surface_ss / s2, surface_limit, surface_dof);
  return rem;
}

std::optional<Decision> at_the_end_of_its_range(const Candidate& c) {
  for (size_t e = 0; e < c.effects.size(); ++e) {
    const auto specs = effects::make_effect(c.effects[e].type)->parameters();
    for (size_t k = 0; k < specs.size(); ++k) {
      const double v = c.effects[e].values[k], end = 1e-6 * (specs[k].hi - specs[k].lo);
      if (specs[k].fitted && (v <= specs[k].lo + end || v >= specs[k].hi - end))
        return Decision{Reason::at_end_of_range, c.effects[e].type + "." + specs[k].key, {},
                        {{"value", v}, {"lo", specs[k].lo}, {"hi", specs[k].hi}}};
    }
  }
  return std::nullopt;
}

std::optional<Decision> not_measured(const Candidate& c) {
  if (auto at_end = at_the_end_of_its_range(c)) return at_end;
  for (size_t e = 0; e < c.effects.size(); ++e)
    for (const auto& p : c.parameters[e])
      if (p.fitted && !p.determined)
        return Decision{Reason::not_determined, c.effects[e].type + "." + p.key, {},
                        {{"value", p.value}, {"sd", p.uncertainty}}};
  return std::nullopt;
}

LibraryJudgement judge_library(const Context& ctx, const LibraryFits& library, const PairFits& pairs) {
  LibraryJudgement j;
  // Not an explanation, whatever its ΔBIC (issue 14): a remainder that is more than noise (the explanation does not
  // make the pattern; a "partly explained" culprit reads as the culprit). Then nothing is picked: it becomes the
  // nearest, with why.
  if (pairs.pick) {
    Remainder rem = remainder_with(ctx, &*pairs.pick);
    Candidate pick = *pairs.pick;
    pick.rms_after_um = rem.rms_um(ctx.n);
    if (rem.excess) {
      pick.rejection = rem.excess;
      pick.significant = false;
      j.refused = pick;
      j.nearest = pick;
      j.nearest_rejection = rem.excess;
    } else {
      j.pick = std::move(pick);
      j.remainder = std::move(rem);
    }
  }
  if (!j.pick) j.remainder = remainder_with(ctx, nullptr);
  // Nothing picked: the nearest is the best fit by ΔBIC, rejected ones included.
  if (!j.nearest && !j.pick && !library.ranked.empty()) {
    j.nearest = *std::min_element(library.ranked.begin(), library.ranked.end(),
                                  [](const Candidate& a, const Candidate& b) { return a.delta_bic < b.delta_bic; });
    j.nearest_rejection = why_not_picked(ctx, *j.nearest);
  }
  j.unexplained = !j.pick && j.remainder.excess.has_value();
  // A value that is no measurement (at the end of its range, not determined), parts that cancel or a library rival
  // within the threshold: the machine elements are tried beside it (try_families).
  if (j.pick) {
    j.not_measured = not_measured(*j.pick);
    if (!j.not_measured) j.not_measured = parts_cancel(ctx, *j.pick);
    if (!j.not_measured)
      if (const auto rivals = library_rivals(ctx, library, pairs, *j.pick); !rivals.empty())
        j.not_measured = Decision{Reason::ambiguous, j.pick->name(), {j.pick->name(), rivals.front().name()}, {}};
  }
  return j;
}

} // namespace geartopo::diagnosis::stages
