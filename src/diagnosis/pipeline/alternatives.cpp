// geartopo diagnosis — stage 5 (stages.hpp): what competes with the named explanation. Units: µm, unit-free ΔBIC.
#include "stages.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <utility>

namespace geartopo::diagnosis::stages {
namespace {

using Outcome = BeyondLibrary::Outcome;

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

/// How much of A's columns lies in B's span (0 … 1, unit-free): ‖Q_Bᵀ A‖_F / ‖A‖_F.
double share_in_span(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(B);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(B.rows(), B.cols());
  const double a = A.norm();
  return a > 0.0 ? (Q.transpose() * A).norm() / a : 0.0;
}

/// Hypothesis k's equivalence class among hypotheses k+1 … end−1: its own aliases (a periodic order's the measured
/// teeth cannot tell from it), and the hypotheses as plausible as it (both rejected or neither) within the threshold
/// whose fields are alike both ways (set-up terms removed): their columns span each other, or each one's field at its
/// fitted values lies in the other's columns — what the data see of a hypothesis with more parameters than its field
/// needs (a wheel profile wearing in slope and crowning per stroke at the ratio an A-axis drift's one rate makes).
std::vector<std::string> equivalence_class(const Context& ctx, const BeyondLibrary& b, std::size_t k, std::size_t end) {
  const auto& hyps = b.hypotheses;
  const Candidate& best = hyps[k];
  std::vector<std::string> names = best.equivalent;
  const auto judged_field = [&](const Candidate& h) { // n × 1
    return b.states->judged(Eigen::MatrixXd(hypothesis_field(h, *b.states)));
  };
  const Eigen::MatrixXd best_columns = b.states->judged(best.family->columns(best, *b.states));
  std::optional<Eigen::MatrixXd> best_field;
  for (size_t a = k + 1; a < end; ++a) {
    const Candidate& c = hyps[a];
    if (c.is_rejected() != best.is_rejected() || c.delta_bic >= best.delta_bic + ctx.options.bic_threshold) continue;
    const Eigen::MatrixXd other = b.states->judged(c.family->columns(c, *b.states));
    double alike = std::min(share_in_span(other, best_columns), share_in_span(best_columns, other));
    if (alike < ctx.options.alike_share && (other.cols() > 1 || best_columns.cols() > 1)) {
      if (!best_field) best_field = judged_field(best);
      alike = std::min(share_in_span(judged_field(c), best_columns), share_in_span(*best_field, other));
    }
    if (alike >= ctx.options.alike_share) names.push_back(c.name());
  }
  return names;
}

/// The classes of the listed hypotheses after the best (DiagnoseOptions::hypotheses_listed), each among the listed
/// ones: a hypothesis already in an earlier one's class has none of its own (it is listed in that row).
std::vector<std::vector<std::string>> listed_classes(const Context& ctx, const BeyondLibrary& b,
                                                     const std::vector<std::string>& best_class) {
  const std::size_t listed = std::min(b.hypotheses.size(), ctx.options.hypotheses_listed);
  std::vector<std::vector<std::string>> classes(listed);
  std::vector<std::string> placed = best_class;
  for (std::size_t k = 1; k < listed; ++k) {
    if (std::find(placed.begin(), placed.end(), b.hypotheses[k].name()) != placed.end()) continue;
    for (auto& name : equivalence_class(ctx, b, k, listed)) // a member of an earlier row stays there
      if (std::find(placed.begin(), placed.end(), name) == placed.end()) classes[k].push_back(std::move(name));
    placed.insert(placed.end(), classes[k].begin(), classes[k].end());
  }
  return classes;
}

/// The library's explanations that can leave a named element's field on these flanks: at least alike_share of it
/// (set-up terms removed) lies in the span of the explanation's parameter columns at its fitted values.
std::vector<std::string> library_look_alikes(const Context& ctx, const LibraryFits& library, const Candidate& h,
                                             const ContactStates& states) {
  std::vector<std::string> names;
  const Eigen::VectorXd mine = ctx.setup_terms.remove(hypothesis_field(h, states));
  for (const auto& c : library.ranked)
    if (!c.effects.empty() && mine.norm() > 0.0 &&
        share_of_field_in_span(mine, library_columns(ctx, c)) >= ctx.options.alike_share)
      names.push_back(c.name());
  return names;
}

/// Every user's own effect fitted alone, against every library effect fitted alone and every listed machine element:
/// the share of its field each can make (Candidate::look_alikes), highest first. The same test as a named element's
/// library look-alikes, reported as a number for every pair: the user judges whether their law is new physics.
std::map<std::string, std::vector<std::pair<std::string, double>>>
own_effect_look_alikes(const Context& ctx, const LibraryFits& library, const BeyondLibrary& beyond) {
  std::map<std::string, std::vector<std::pair<std::string, double>>> out;
  const auto is_own = [&](const Candidate& c) {
    return c.effects.size() == 1 && std::find(ctx.options.own_effects.begin(), ctx.options.own_effects.end(),
                                              c.effects.front().type) != ctx.options.own_effects.end();
  };
  if (std::none_of(library.ranked.begin(), library.ranked.end(), is_own)) return out; // the columns cost fits
  std::vector<std::pair<std::string, Eigen::MatrixXd>> others; // name, n × P columns
  for (const auto& c : library.ranked)
    if (!c.effects.empty() && !is_own(c)) others.emplace_back(c.name(), library_columns(ctx, c));
  const std::size_t listed = std::min(beyond.hypotheses.size(), ctx.options.hypotheses_listed);
  for (std::size_t k = 0; k < listed && beyond.states; ++k)
    others.emplace_back(beyond.hypotheses[k].name(),
                        Eigen::MatrixXd(ctx.setup_terms.remove(hypothesis_field(beyond.hypotheses[k], *beyond.states))));
  for (const auto& c : library.ranked) {
    if (!is_own(c)) continue;
    const Eigen::VectorXd mine = explanation_field(ctx, c);
    auto& list = out[c.name()];
    for (const auto& [name, columns] : others) list.emplace_back(name, share_of_field_in_span(mine, columns));
    std::stable_sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  }
  return out;
}

} // namespace

/// Ambiguity: a plausible explanation whose ΔBIC is within the threshold of the pick's is not told apart from it by
/// these data (the same rule that makes an effect significant against none). A nested explanation (the pick with one
/// more effect, or the picked pair's half) is a rival only when it is the better fit without being better by the
/// threshold: a worse superset is just the pick plus a partner the data do not ask for, and the smaller half of a taken
/// pair lost by the threshold already. Another physics that loses only on BIC's parameter count is not told apart either:
/// when AIC (the fit plus 2 per parameter, what the extra parameters buy on noise alone) does not prefer the pick, the
/// penalty is Occam's, not the measurement's (a true thermal drift at 1.5 µm noise on two teeth fits better than wear,
/// yet pays 2 ln n for a Z growth and a time constant they cannot fix). Not significant alone is no reason to drop a
/// rival: within the threshold of the pick, the data do not prefer the pick either.
std::vector<Candidate> library_rivals(const Context& ctx, const LibraryFits& library, const PairFits& pairs,
                                      const Candidate& pick) {
  const double threshold = ctx.options.bic_threshold, ln_n = ctx.ln_n();
  const auto nested = [&](const Candidate& c) { return c.nested_in(pick) || pick.nested_in(c); };
  const auto aic = [&](const Candidate& x) { return x.delta_bic - x.fitted_parameters() * (ln_n - 2.0); };
  const auto rival = [&](const Candidate& c) {
    if (c.is_rejected() || c.name() == pick.name()) return false;
    if (nested(c))
      return c.effects.size() > pick.effects.size() &&
             (c.delta_bic < pick.delta_bic ||
              (c.delta_bic < pick.delta_bic + threshold && confounded_partner(c, pick)));
    return c.delta_bic < pick.delta_bic + threshold || aic(c) <= aic(pick);
  };
  std::vector<Candidate> rivals;
  for (const auto& c : library.ranked)
    if (rival(c)) rivals.push_back(c);
  for (const auto& c : pairs.pairs)
    if (rival(c)) rivals.push_back(c);
  std::stable_sort(rivals.begin(), rivals.end(),
                   [](const Candidate& a, const Candidate& b) { return a.delta_bic < b.delta_bic; });
  // The plan separates the pick from its best rival of other physics first; whether a partner comes with it (a nested
  // rival) is the second question, asked when no other rival is left.
  std::stable_partition(rivals.begin(), rivals.end(), [&](const Candidate& c) { return !nested(c); });
  return rivals;
}

Alternatives find_alternatives(const Context& ctx, const LibraryFits& library, const PairFits& pairs,
                               const LibraryJudgement& judgement, const BeyondLibrary& beyond) {
  Alternatives a;
  a.own_look_alikes = own_effect_look_alikes(ctx, library, beyond);
  if (judgement.pick) a.rivals = library_rivals(ctx, library, pairs, *judgement.pick);
  if (!beyond.tried() || beyond.hypotheses.empty()) return a;
  a.equivalent = equivalence_class(ctx, beyond, 0, beyond.hypotheses.size());
  a.listed_classes = listed_classes(ctx, beyond, a.equivalent);
  if (beyond.outcome == Outcome::rival) a.rivals.insert(a.rivals.begin(), *beyond.best);
  if (beyond.outcome != Outcome::named) return a;
  // A named element: the library look-alikes, and rivals only beyond the library — within the threshold with a
  // different field (the verdict says "ambiguous between", the plan what separates them). An equivalent one is not:
  // one class, said as such.
  const Candidate& h = *beyond.best;
  a.library_equivalent = library_look_alikes(ctx, library, h, *beyond.states);
  a.rivals.clear();
  for (size_t k = 1; k < beyond.hypotheses.size(); ++k) {
    const Candidate& c = beyond.hypotheses[k];
    if (c.is_rejected() || c.delta_bic >= h.delta_bic + ctx.options.bic_threshold) continue;
    if (std::find(a.equivalent.begin(), a.equivalent.end(), c.name()) != a.equivalent.end()) {
      if (!a.equivalent_member) a.equivalent_member = c;
      continue;
    }
    a.rivals.push_back(c);
  }
  return a;
}

} // namespace geartopo::diagnosis::stages
