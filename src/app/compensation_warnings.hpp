// geartopo — when compensation would do harm: the paper method on a drawing's helix modifications (refused), and a
// gear made worse in the model or in the prediction (warned, on stderr and in iso1328.json "warnings").
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace geartopo::pipeline {
struct MonteCarloSummary;
}
namespace geartopo::workbench {
struct Workbench;
}

namespace geartopo::app {

/// When compensation made the gear worse — the largest |deviation| after is above the one before by more than
/// kWorseToleranceUm — the sentence to warn with (stderr and iso1328.json "warnings"), with the growth in µm and, when
/// the gear before was not already within kWorseToleranceUm of perfect, in percent; otherwise empty. E.g. the paper
/// method cancels a rotation that does not touch the flank (ε_yy, ε_ya) through the other axes and spoils the gear.
inline constexpr double kWorseToleranceUm = 0.01; ///< far below any tolerance, far above the simulation's rounding
std::string compensation_made_worse(double before_um, double after_um);

/// When the PREDICTED gear (Monte Carlo) is worse after compensation than before — a coarser median overall class,
/// or a median largest |deviation| above the whole 95 % interval before — the sentence to warn with; otherwise empty.
/// The usual cause: corrections smaller than the command resolution, rounded into steps (docs/monte-carlo.md).
std::string prediction_made_worse(const pipeline::MonteCarloSummary& prediction);

/// `--method paper` drives the wheel's pose to the nominal one at every pose, which would take away the design
/// motions that grind the drawing's helix modifications (docs/modifications.md): refused on such a scene
/// (CLI::ValidationError naming --method, exit 2). The flank and cycle methods correct towards the design.
void refuse_paper_on_a_designed_helix(const std::string& method, const workbench::Workbench& wb);

/// When the scene's machine has no error map (no machine.tables, constants or polynomials: docs/scene-format.md calls
/// it an error-free machine), the note `compensate` prints before its numbers: the nominal deviations come only from
/// the effects and changes the scene lists (none: they and the corrections are 0), and a prediction's spread only from
/// the uncertainties — the defaults unless the scene states them. Empty when the scene has a map.
std::string error_free_machine_note(const workbench::Workbench& wb);

/// `warning`, when there is one, on stderr and in iso1328.json's "warnings" (`iso`).
void add_warning(nlohmann::json& iso, const std::string& warning);

} // namespace geartopo::app
