// geartopo diagnosis — stage 7 (stages.hpp): the Diagnosis assembled from every stage's result, with its records, and
// the verdict composed from them. Units: µm.
#include "stages.hpp"

#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/residuals/flank_patterns.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace geartopo::diagnosis::stages {
namespace {

using Outcome = BeyondLibrary::Outcome;

/// What a thermal drift with an undetermined amplitude or time constant still fixes: its X and Z growth between t1 and
/// t2 (s). δ(t) = g·(1 − e^(−t/τ)), so Δ = g·(e^(−t1/τ) − e^(−t2/τ)); 1σ by the delta method from the linearised
/// covariance. Empty for another effect or when its values are all determined.
std::vector<DeterminedGrowth> thermal_growth_determined(const Candidate& c, double t1_s, double t2_s) {
  std::vector<DeterminedGrowth> out;
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
        out.push_back({g == x ? "X" : "Z", delta, std::sqrt(std::max(var, 0.0)), t1_s, t2_s});
      }
    }
    for (const auto& p : params) slot += p.fitted ? 1 : 0;
  }
  return out;
}

/// Set-up values assumed, not fitted: every unfitted parameter of what the verdict names (chosen, rivals, nearest).
std::vector<AssumedValue> assumed_values(const Diagnosis& d) {
  std::vector<const Candidate*> named;
  if (d.chosen) named.push_back(&*d.chosen);
  for (const auto& r : d.rivals) named.push_back(&r);
  if (d.nearest) named.push_back(&*d.nearest);
  std::vector<AssumedValue> out;
  for (const Candidate* c : named)
    for (size_t e = 0; e < c->effects.size(); ++e)
      for (const auto& p : c->parameters[e]) {
        if (p.fitted) continue;
        const AssumedValue a{c->effects[e].type, p.key, p.value};
        const bool listed = std::any_of(out.begin(), out.end(), [&](const AssumedValue& b) {
          return b.effect == a.effect && b.key == a.key && to_text(b) == to_text(a);
        });
        if (!listed) out.push_back(a);
      }
  return out;
}

/// The pattern of a residual r (µm, set-up terms removed): the two largest named patterns (docs/residual-patterns.md)
/// averaged over the measured flanks with their spread — largest by how far the flanks reach, not the mean alone (a
/// pattern growing from tooth to tooth averages small) — and the RMS per tooth.
ResidualPattern residual_pattern(const Context& ctx, const std::vector<double>& r) {
  PatternOptions po;
  po.noise_um = ctx.noise_um;
  std::vector<FlankPatterns> fitted;
  for (const auto& f : flank_residuals(ctx.setup.ranges(), ctx.points, r)) {
    try {
      fitted.push_back(fit_flank_patterns(f, po));
    } catch (const std::invalid_argument&) { // too few distinct positions on this flank for the six patterns
    }
  }
  ResidualPattern out;
  out.flanks = static_cast<int>(fitted.size());
  if (!fitted.empty()) {
    std::vector<ResidualPattern::Spread> spreads;
    for (NamedPattern p : kNamedPatterns) {
      ResidualPattern::Spread s{std::string(to_string(p)), 0.0, 1e300, -1e300};
      for (const auto& f : fitted) {
        const double v = pattern_value(f, p).value;
        s.mean_um += v / static_cast<double>(fitted.size()), s.lo_um = std::min(s.lo_um, v), s.hi_um = std::max(s.hi_um, v);
      }
      spreads.push_back(s);
    }
    const auto reach = [](const ResidualPattern::Spread& s) { return std::max(std::abs(s.lo_um), std::abs(s.hi_um)); };
    std::stable_sort(spreads.begin(), spreads.end(), [&](const auto& a, const auto& b) { return reach(a) > reach(b); });
    out.largest.assign(spreads.begin(), spreads.begin() + 2);
  }
  std::map<int, std::pair<double, int>> per_tooth; // tooth → (Σ r², count)
  for (size_t i = 0; i < ctx.points.size(); ++i)
    per_tooth[ctx.points[i].tooth].first += r[i] * r[i], ++per_tooth[ctx.points[i].tooth].second;
  for (const auto& [tooth, ss] : per_tooth) out.tooth_rms_um.emplace_back(tooth, std::sqrt(ss.first / ss.second));
  return out;
}

/// The library's single effects as listed: the pick refused against the noise said so where it stands, and — when
/// nothing is named from the library nor beyond it — none significant that explains less than the nearest, which is
/// no explanation either.
std::vector<Candidate> ranked_as_listed(const LibraryFits& library, const LibraryJudgement& j, bool nothing_named) {
  std::vector<Candidate> ranked = library.ranked;
  if (j.refused)
    for (auto& c : ranked)
      if (c.name() == j.refused->name()) c.rejection = j.refused->rejection, c.significant = false;
  if (nothing_named && j.nearest)
    for (auto& c : ranked)
      if (c.significant) {
        c.significant = false;
        c.rejection = Decision{Reason::explains_less, c.name(), {j.nearest->name()}, {}};
      }
  return ranked;
}

/// The families' hypotheses as listed: the best one with what later stages found of it, then the rest, at most
/// DiagnoseOptions::hypotheses_listed.
std::vector<Candidate> hypotheses_as_listed(const Context& ctx, const BeyondLibrary& b, const Alternatives& a) {
  std::vector<Candidate> hyps = b.hypotheses;
  if (hyps.empty()) return hyps;
  if (b.best) hyps.front() = *b.best;
  hyps.front().equivalent = a.equivalent;
  for (std::size_t k = 1; k < hyps.size() && k < a.listed_classes.size(); ++k)
    if (!a.listed_classes[k].empty()) hyps[k].equivalent = a.listed_classes[k]; // its aliases included
  if (b.outcome == Outcome::named) hyps.front().library_equivalent = a.library_equivalent;
  if (hyps.size() > ctx.options.hypotheses_listed) hyps.resize(ctx.options.hypotheses_listed);
  return hyps;
}

} // namespace

Diagnosis compose(const Context& ctx, std::optional<Decision> reference, const LibraryFits& library,
                  const PairFits& pairs, const LibraryJudgement& j, const BeyondLibrary& b, const Alternatives& a,
                  Plans plans, std::optional<PosteriorDraws> draws) {
  Diagnosis d;
  d.reference_in_doubt = std::move(reference);
  d.points = static_cast<int>(ctx.points.size());
  d.noise_um = ctx.noise_um, d.noise_estimated = ctx.noise_estimated;
  d.rms_before_um = ctx.rms_before_um, d.rms_before_setup_um = ctx.rms_before_setup_um;
  d.residual_before_um = ctx.residual_before_um;
  const bool named = b.outcome == Outcome::named;
  d.beyond_library = named;
  d.hypotheses = hypotheses_as_listed(ctx, b, a);
  if (named) {
    d.chosen = d.hypotheses.front();
    d.nearest = j.pick ? j.pick : j.nearest; // the library's explanation whose value is no measurement, with why
    d.nearest_rejection = j.pick ? j.not_measured : j.nearest_rejection;
  } else {
    d.chosen = j.pick;
    d.nearest = j.nearest, d.nearest_rejection = j.nearest_rejection;
  }
  d.ranked = ranked_as_listed(library, j, !d.chosen);
  for (auto& c : d.ranked)
    if (const auto it = a.own_look_alikes.find(c.name()); it != a.own_look_alikes.end()) c.look_alikes = it->second;
  if (d.chosen)
    if (const auto it = a.own_look_alikes.find(d.chosen->name()); it != a.own_look_alikes.end())
      d.chosen->look_alikes = it->second;
  if (pairs.combination && !(j.refused && j.refused->name() == pairs.combination->name())) d.combination = pairs.combination;
  d.rivals = a.rivals;
  d.unexplained = j.unexplained && !named;
  const Remainder& rem = named ? *b.remainder : j.remainder;
  d.residual_after_um.assign(rem.removed.data(), rem.removed.data() + rem.removed.size());
  d.rms_after_um = rem.rms_um(ctx.n);
  d.setup = ctx.setup_terms.fit(rem.raw, std::sqrt(rem.judged.squaredNorm() / rem.dof));
  d.chi2_after = rem.judged.squaredNorm() / (ctx.noise_um * ctx.noise_um);
  d.chi2_dof = rem.dof;
  d.remainder_excess = rem.excess;
  if (d.unexplained) d.residual_pattern = residual_pattern(ctx, d.residual_after_um);
  if (b.tried()) d.beyond_trigger = j.not_measured;
  if (b.outcome == Outcome::rejected) d.nearest_element = b.best;
  d.element_kept_out = b.kept_out;
  d.plan = std::move(plans.plan), d.equivalent_plan = std::move(plans.equivalent_plan);
  // A value pushed against the end of its allowed range is no measurement (thermal drift's amplitude trading against
  // its time constant on two teeth): the effect explains the residual, but is not added with that value.
  if (d.chosen && !d.rivals.empty())
    d.withheld = Decision{Reason::ambiguous, d.chosen->name(), {d.chosen->name(), d.rivals.front().name()}, {}};
  else if (d.chosen)
    d.withheld = at_the_end_of_its_range(*d.chosen);
  // An explanation of a residual that may be the drawing read as a fault is not added until the reference is said.
  if (d.chosen && !d.withheld) d.withheld = d.reference_in_doubt;
  d.assumed = assumed_values(d);
  if (d.chosen) d.determined = thermal_growth_determined(*d.chosen, ctx.first_time_s, ctx.last_time_s);
  d.draws = std::move(draws);
  d.verdict = verdict_text(d, ctx.options);
  return d;
}

} // namespace geartopo::diagnosis::stages
