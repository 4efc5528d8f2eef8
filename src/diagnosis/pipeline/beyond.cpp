// geartopo diagnosis — stage 4 (stages.hpp): the families beyond the library, and what their best hypothesis does to
// the library's explanation. Units: µm.
#include "stages.hpp"

namespace geartopo::diagnosis::stages {
namespace {

using Outcome = BeyondLibrary::Outcome;

/// The share of the best hypothesis' field (set-up terms removed) that the pick's parameter columns can make: at least
/// alike_share, and the pick can leave the same field.
double share_the_pick_can_make(const Context& ctx, const ContactStates& states, const Candidate& h,
                               const Candidate& pick) {
  const Eigen::VectorXd mine = ctx.setup_terms.remove(hypothesis_field(h, states));
  if (mine.norm() == 0.0) return 0.0;
  return share_of_field_in_span(mine, library_columns(ctx, pick));
}

} // namespace

// Beyond the library (docs/diagnosis.md): when nothing in it explains the residual, the families' hypotheses — the
// chain's own error components under their laws, each wheel flank's profile and waviness, the wheel profile's wear.
// The best plausible, significant one that leaves noise is named (with its equivalence class: find_alternatives); one
// that leaves more is the nearest machine element, and the residual stays unexplained.
// Also when what the library leaves passes as noise: a hypothesis faces the test a library effect faces (ΔBIC below
// −threshold), not the χ² test of the whole remainder, whose hundreds of degrees of freedom dilute a one-parameter
// field (an A-axis drift of 20 … 40 µrad/min on ten teeth: χ² 511 … 605 against the limit 608 on 498 degrees of
// freedom, while its own fit reaches ΔBIC −18 … −53).
// Also when the library's explanation is ambiguous (a library rival within the threshold), or holds a value that is no
// measurement: at the end of its allowed range (a thermal
// drift whose time constant runs away turns into a drift rate) or not determined by the data (a thermal drift and a
// wear of opposite signs cancelling into the profile slope an A-axis drift makes), or a pair whose parts cancel. A
// machine element whose law the data do determine is named instead when it fits better — by the threshold when the
// library's explanation can leave the same field (an X axis approaching a steady state is a thermal X growth: the
// library's physics stays named, with what the data fix of it); fitting worse within the threshold, with another field,
// it is a rival (a C-axis radial motion beside a thermal drift whose time constant skip-indexed teeth do not fix).
BeyondLibrary try_families(const Context& ctx, const LibraryJudgement& j) {
  BeyondLibrary b;
  if (j.pick && !j.not_measured) return b;
  const double threshold = ctx.options.bic_threshold;
  std::vector<int> teeth;
  for (const auto& p : ctx.points) teeth.push_back(p.tooth);
  b.states = std::make_unique<ContactStates>(ctx.setup, ctx.at_points, &ctx.setup_terms, ctx.options.threads, teeth,
                                             ctx.options.keep_going);
  b.hypotheses = fit_hypotheses(ctx, *b.states);
  b.outcome = Outcome::not_usable;
  if (b.hypotheses.empty()) return b;
  const Candidate& front = b.hypotheses.front();
  const bool usable = !front.rejection && front.delta_bic < -threshold &&
                      (!j.pick || front.delta_bic < j.pick->delta_bic + threshold);
  if (!usable) return b;
  double share = 0.0;
  if (j.pick) share = share_the_pick_can_make(ctx, *b.states, front, *j.pick);
  const bool same_field = j.pick && share >= ctx.options.alike_share;
  // The same field: the element takes the place only when the data prefer it by the threshold (the library's
  // explanation then spends more parameters than the data determine on it: an A-axis drift as a thermal drift and a
  // wear cancelling each other).
  const bool element_first = !j.pick || front.delta_bic < j.pick->delta_bic - (same_field ? threshold : 0.0);
  b.best = front;
  if (!element_first) {
    if (same_field) {
      b.outcome = Outcome::kept_out;
      b.kept_out = Decision{Reason::element_kept_out, front.description, {j.pick->name()},
                            {{"delta_bic", front.delta_bic}, {"threshold", threshold}, {"field_share", share}}};
      b.best.reset();
    } else {
      b.outcome = Outcome::rival;
      b.best->rms_after_um = remainder_with(ctx, &front).rms_um(ctx.n);
    }
    return b;
  }
  Remainder rem = remainder_with(ctx, &front);
  b.best->rms_after_um = rem.rms_um(ctx.n);
  if (!rem.excess) {
    b.outcome = Outcome::named;
    b.best->significant = true;
  } else if (j.unexplained) {
    b.outcome = Outcome::rejected;
    Decision why = *rem.excess;
    why.subject = front.name();
    b.best->rejection = std::move(why);
  } else {
    b.outcome = Outcome::not_noise;
  }
  b.remainder = std::move(rem);
  return b;
}

} // namespace geartopo::diagnosis::stages
