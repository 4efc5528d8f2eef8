// geartopo diagnosis — stage 1 (stages.hpp): every effect of the library the scene does not model, fitted alone to
// the residual with the set-up terms. Units: µm and each parameter's own unit.
#include "stages.hpp"

#include "geartopo/effects/registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace geartopo::diagnosis::stages {
namespace {

/// An effect a family beyond the library tries (one wheel flank or one grid point at a time): not a library
/// candidate of its own — one wheel flank's profile error as a library candidate would stand its four parameters beside
/// wheel_profile's two for every symmetric dressing error, the wheel profile's wear would meet a wheel_wear +
/// wheel_profile pair in every ranked table.
bool family_effect(const Context& ctx, const std::string& type) {
  return std::any_of(ctx.options.families.begin(), ctx.options.families.end(),
                     [&](const auto& f) { return f->effect_type() == type; });
}

/// The candidates: the ones asked for, or every library effect and the user's own; never one the scene already models
/// (fitting it again would stack two copies and write a scene that lists it twice), never one twice.
std::vector<std::string> candidate_types(const Context& ctx) {
  const auto& o = ctx.options;
  const bool asked = !o.candidates.empty();
  std::vector<std::string> types, all = effects::effect_types();
  all.insert(all.end(), o.own_effects.begin(), o.own_effects.end());
  for (const auto& t : asked ? o.candidates : all) {
    if (!asked && family_effect(ctx, t)) continue;
    const bool modelled = std::find(ctx.in_scene.begin(), ctx.in_scene.end(), t) != ctx.in_scene.end();
    if (modelled && asked)
      throw std::invalid_argument(fmt::format("diagnose: candidate '{}' is already in the scene's effects", t));
    if (!modelled && std::find(types.begin(), types.end(), t) == types.end()) types.push_back(t);
  }
  return types;
}

} // namespace

LibraryFits fit_library(const Context& ctx, FitProgress& progress) {
  LibraryFits out;
  const auto types = candidate_types(ctx);
  progress.known += static_cast<long long>(types.size());
  for (const auto& t : types) {
    Candidate c = fit_effects(ctx.setup, ctx.at_points, ctx.residual_before_um, {t}, {}, ctx.setup_terms, ctx.options,
                              ctx.search());
    c.significant = c.delta_bic < -ctx.options.bic_threshold && !c.rejection;
    out.values[t] = c.effects.front().values;
    out.ranked.push_back(std::move(c));
    progress.fitted();
  }
  std::sort(out.ranked.begin(), out.ranked.end(),
            [](const Candidate& a, const Candidate& b) { return a.delta_bic < b.delta_bic; });
  // Rejected candidates (implausible parameters) go after the others, whatever their ΔBIC: the best explanation is
  // the first plausible significant one.
  std::stable_partition(out.ranked.begin(), out.ranked.end(), [](const Candidate& c) { return !c.rejection; });
  return out;
}

} // namespace geartopo::diagnosis::stages
