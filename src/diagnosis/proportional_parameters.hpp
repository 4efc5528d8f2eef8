// geartopo diagnosis, private — which parameters of a user's law the deviation is proportional to, found numerically
// at the measured points (docs/diagnosis.md, "Your own effects"): the fit solves those by variable projection
// (effect_fit.cpp). Units: µm (fields), each parameter in its own unit.
#pragma once

#include "geartopo/diagnosis/effect_contribution.hpp"
#include "geartopo/effects/effect.hpp"

#include <cstddef>
#include <vector>

namespace geartopo::diagnosis {

/// The fitted parameters S of `effect` (bound to the set-up; its values the fit's neutral starts) whose field at the
/// points is jointly proportional to them: d(θ_S, θ_N) = Σ_{k∈S} θ_k b_k(θ_N), zero when they are all zero. Tried:
/// every fitted parameter whose range holds 0 and that is no count. Checked at two settings of the others (the
/// neutral starts, and each moved 37 % of the way to its upper bound): with θ_S = 0 the field is 0; for each k the
/// fields at θ_k = a and 2a (a its typical size, the rest of S at 0) are collinear, d(2a) = 2 d(a), and not zero;
/// and they add, d(Σ a e_k) = Σ d(a e_k) — each to 10⁻⁹ of the fields' size. A parameter that fails (or whose field
/// alone is zero: a product a·b is proportional to each, not to both) leaves S and the checks start again with it
/// among the others. Costs at most 2·(2|S| + 2) evaluations of the law per round, |S| + 1 rounds.
std::vector<std::size_t> proportional_parameters(const effects::Effect& effect, const EffectContribution& at, int threads);

} // namespace geartopo::diagnosis
