#include "app/compensation_warnings.hpp"

#include "app/messages.hpp"

#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

namespace geartopo::app {

namespace {

/// The cause of a worse after-state, as the decomposition by source measured it (pipeline::after_limit): "without the
/// rounding to machine.resolution the median class is 4 (f_fβ 6.33 → 0.56 µm): it sets the class", or, when the
/// samples were exact (no decomposition), that it was not measured.
std::string measured_cause(const pipeline::MonteCarloSummary& p) {
  const auto limit = pipeline::after_limit(p);
  if (!limit.measured)
    return "the cause was not measured (exact samples: no decomposition by source); check machine.resolution against "
           "the corrections and the uncertainties before applying them";
  for (const auto& w : limit.without)
    if (w.source == limit.dominant)
      return fmt::format("without {} the median class is {:g} ({} {:.2f} → {:.2f} µm): it sets the class after",
                         report::source_label(w.source), w.overall_class, report::quantity_label(limit.limiting_quantity),
                         limit.limiting_median_um, w.limiting_median_um);
  return {};
}

} // namespace

void refuse_paper_on_a_designed_helix(const std::string& method, const workbench::Workbench& wb) {
  if (method == "paper" && wb.design_motion)
    throw CLI::ValidationError("--method", "paper drives the wheel to its nominal pose and would grind away the drawing's "
                                           "helix modifications (gear.modifications): use flank or cycle, which correct "
                                           "towards the design");
}

std::string compensation_made_worse(double before_um, double after_um) {
  if (!(after_um > before_um + kWorseToleranceUm)) return {};
  // A percentage of a "before" that is zero within the simulation's rounding is meaningless (finding 20).
  const std::string growth = before_um > kWorseToleranceUm
                                 ? fmt::format("{:+.3f} µm, {:+.1f} %", after_um - before_um, 100.0 * (after_um - before_um) / before_um)
                                 : fmt::format("{:+.3f} µm from a gear that was perfect", after_um - before_um);
  return fmt::format("compensation made the gear worse even in the model: nominal (the model corrected by itself), the "
                     "largest |deviation| grows from {:.3f} to {:.3f} µm ({}); do not apply these corrections (try the "
                     "other --method)",
                     before_um, after_um, growth);
}

std::string prediction_made_worse(const pipeline::MonteCarloSummary& p) {
  const int cls = p.find("overall_class"), largest = p.find("largest_abs_um");
  if (cls >= 0 && p.after[static_cast<size_t>(cls)].median > p.before[static_cast<size_t>(cls)].median)
    return fmt::format("the predicted gear is worse after compensation: overall class {:g} against {:g} before (medians of "
                       "{} samples); {}",
                       p.after[static_cast<size_t>(cls)].median, p.before[static_cast<size_t>(cls)].median, p.samples,
                       measured_cause(p));
  // Medians of a few dozen samples scatter: only an after-median above the whole 95 % interval before is "worse".
  if (largest >= 0 && p.after[static_cast<size_t>(largest)].median > p.before[static_cast<size_t>(largest)].high)
    return fmt::format("the predicted gear is worse after compensation: largest |deviation| {:.2f} µm (median) against "
                       "{:.2f} µm [{:.2f}, {:.2f}] before ({} samples); {}",
                       p.after[static_cast<size_t>(largest)].median, p.before[static_cast<size_t>(largest)].median,
                       p.before[static_cast<size_t>(largest)].low, p.before[static_cast<size_t>(largest)].high, p.samples,
                       measured_cause(p));
  return {};
}

std::string error_free_machine_note(const workbench::Workbench& wb) {
  const auto& s = wb.scene;
  if (!s.machine.sources.empty()) return {};
  const bool nothing = s.effects.empty() && s.machine_changes.empty() && !wb.design_motion;
  return fmt::format("note: the scene's machine has no error map (no machine.tables, constants or polynomials: an "
                     "error-free machine){}; the prediction's spread comes only from the uncertainties (machine."
                     "uncertainty, repeatability, resolution: the defaults where the scene gives none, "
                     "docs/scene-format.md)",
                     nothing ? ", and no effects: its nominal deviations and its corrections are 0"
                             : ": the nominal deviations and corrections come only from its effects, changes and design");
}

void add_warning(nlohmann::json& iso, const std::string& warning) {
  if (warning.empty()) return;
  say("geartopo: warning: " + warning);
  iso["warnings"].push_back(warning);
}

} // namespace geartopo::app
