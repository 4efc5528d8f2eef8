// geartopo diagnosis — stage 6 (stages.hpp): what to measure next. Units: µm.
#include "stages.hpp"

namespace geartopo::diagnosis::stages {

Plans make_plans(const Context& ctx, const std::optional<Candidate>& chosen, const Alternatives& a) {
  Plans p;
  if (!chosen) return p;
  // Every explanation with a field has one (library effects, pairs, hypotheses: measurement_plan.cpp).
  if (!a.rivals.empty())
    p.plan = plan_measurement(ctx.setup, ctx.points, ctx.residual_before_um, *chosen, a.rivals.front(), ctx.noise_um,
                              ctx.options);
  // An equivalence class is no ambiguity, but the user may ask whether another tooth would tell its members apart.
  if (chosen->family && a.equivalent_member)
    p.equivalent_plan = plan_measurement(ctx.setup, ctx.points, ctx.residual_before_um, *chosen, *a.equivalent_member,
                                         ctx.noise_um, ctx.options);
  return p;
}

} // namespace geartopo::diagnosis::stages
