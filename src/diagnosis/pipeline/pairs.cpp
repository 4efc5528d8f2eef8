// geartopo diagnosis — stage 2 (stages.hpp): pairs of library effects, when one alone is significant. Units: µm.
#include "stages.hpp"

#include "geartopo/effects/registry.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

namespace geartopo::diagnosis::stages {
namespace {

/// The partners a joint fit with the best effect is worth although the evidence does not favour them alone: those the
/// joint fit linearised at the single fits points to — what the best one leaves (set-up terms removed) on the best's and
/// a partner's parameter columns (library_columns), one of the partner's parameters at least 2σ from zero (σ from the
/// noise and the columns). Two passes per parameter instead of a nonlinear pair fit, which on 210 000 trace points
/// costs seconds; a partner the linearised fit does not point to cannot be indicated by the pair's fit either.
std::vector<std::string> partners_pointed_to(const Context& ctx, const Candidate& best,
                                             const std::vector<const Candidate*>& partners) {
  std::vector<std::string> pointed;
  if (partners.empty()) return pointed;
  std::vector<std::unique_ptr<effects::Effect>> owned;
  std::vector<const effects::Effect*> list;
  for (const auto& e : best.effects) {
    owned.push_back(effects::make_effect(e.type, e.values, ctx.setup));
    list.push_back(owned.back().get());
  }
  const Eigen::VectorXd left =
      ctx.setup_terms.remove(Eigen::VectorXd(ctx.before - ctx.at_points.deviation_um(list, ctx.options.threads))); // n
  const Eigen::MatrixXd Jb = library_columns(ctx, best); // n × p_b
  for (const Candidate* partner : partners) {
    const Eigen::MatrixXd Jp = library_columns(ctx, *partner); // n × p_p
    if (Jp.cols() == 0) continue;
    Eigen::MatrixXd J(left.size(), Jb.cols() + Jp.cols());
    J << Jb, Jp;
    const Eigen::MatrixXd cov = (J.transpose() * J).completeOrthogonalDecomposition().pseudoInverse(); // (p × p) / σ²
    const Eigen::VectorXd theta = cov * (J.transpose() * left);
    for (Eigen::Index k = Jb.cols(); k < J.cols(); ++k)
      if (cov(k, k) > 0.0 && std::abs(theta(k)) >= 2.0 * ctx.noise_um * std::sqrt(cov(k, k))) {
        pointed.push_back(partner->effects.front().type);
        break;
      }
  }
  return pointed;
}

/// The pairs to fit: every pair among the best ones the evidence favours (ΔBIC below −threshold, also those rejected
/// alone as implausible), up to DiagnoseOptions::pair_candidates of them, and the best with every other effect the
/// linearised joint fit points to.
std::vector<std::pair<std::string, std::string>> pairs_to_fit(const Context& ctx, const LibraryFits& library) {
  const auto& ranked = library.ranked;
  std::vector<const Candidate*> favoured;
  for (const auto& c : ranked)
    if (c.delta_bic < -ctx.options.bic_threshold) favoured.push_back(&c);
  std::stable_sort(favoured.begin() + 1, favoured.end(),
                   [](const Candidate* a, const Candidate* b) { return a->delta_bic < b->delta_bic; });
  std::vector<std::string> top;
  for (const Candidate* c : favoured)
    if (top.size() < ctx.options.pair_candidates) top.push_back(c->effects.front().type);
  // Every pair among them, not only the best with the others: with few teeth one effect can stand in for the
  // partner of two others (thermal drift mimicking wear beside eccentricity on teeth 1, 2, 18, 35 — independent
  // hidden-effect tests), and the true pair then never gets fitted if the stand-in ranks first.
  std::vector<std::pair<std::string, std::string>> pairs;
  for (size_t a = 0; a < top.size(); ++a)
    for (size_t b = a + 1; b < top.size(); ++b) pairs.emplace_back(top[a], top[b]);
  // And the best with every other effect the linearised joint fit points to: a partner whose field the set-up terms
  // and the best one absorb on these teeth can be far from significant alone (wheel wear beside eccentricity on
  // teeth 1 and 18 with skip indexing: alone it is not favoured, and without it a thermal drift with no determined
  // value took its place).
  std::vector<const Candidate*> others;
  for (const auto& c : ranked)
    if (std::find(top.begin(), top.end(), c.effects.front().type) == top.end()) others.push_back(&c);
  for (const auto& t : partners_pointed_to(ctx, ranked.front(), others)) pairs.emplace_back(top.front(), t);
  return pairs;
}

} // namespace

PairFits fit_pairs(const Context& ctx, const LibraryFits& library, FitProgress& progress) {
  PairFits out;
  if (library.ranked.empty() || !library.ranked.front().significant) return out;
  // Pairs by evidence, not by a gate on the residual: whenever two or more effects are significant alone, the best
  // is fitted jointly with each of the next ones (warm-started from the single fits), and a pair is taken when it
  // beats the best single effect by the ΔBIC threshold again. A few joint fits cost little beside the evidence a
  // fixed "residual > 1.5 σ" gate throws away (with hundreds of points 1.2 σ is already a highly significant excess).
  // Partners rejected alone are tried too: an effect forced to mimic another's pattern on its own can take
  // implausible values and be plausible beside it. The pair faces the plausibility rule itself.
  const auto pairs = pairs_to_fit(ctx, library);
  progress.known += static_cast<long long>(pairs.size());
  const double best_single = library.ranked.front().delta_bic;
  for (const auto& [first, second] : pairs) {
    Candidate c = fit_effects(ctx.setup, ctx.at_points, ctx.residual_before_um, {first, second}, library.values,
                              ctx.setup_terms, ctx.options, ctx.search());
    c.significant = c.delta_bic < best_single - ctx.options.bic_threshold && !c.rejection;
    progress.fitted();
    if (c.significant && (!out.combination || c.delta_bic < out.combination->delta_bic)) out.combination = c;
    out.pairs.push_back(std::move(c));
  }
  out.pick = out.combination ? out.combination : std::optional<Candidate>(library.ranked.front());
  return out;
}

} // namespace geartopo::diagnosis::stages
