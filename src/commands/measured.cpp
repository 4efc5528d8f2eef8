// geartopo — the commands on a measurement, once for every front end (measured.hpp). Units: µm.
#include "geartopo/commands/measured.hpp"

#include "geartopo/commands/limits.hpp"
#include "geartopo/diagnosis/diagnosis_json.hpp"
#include "geartopo/diagnosis/identified_effects.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/diagnosis/scene_writer.hpp"
#include "geartopo/diagnosis/stroke_scatter.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/report/measurement_report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace geartopo::commands {
namespace {

diagnosis::Diagnosis run_diagnosis(const SceneInput& scene, const MeasuredInput& measured, const DiagnoseRequest& r,
                                   const ArgumentNames& names) {
  check_noise_um(r.noise_um, names.noise);
  for (const auto& c : r.candidates)
    if (!effects::make_effect(c))
      throw ArgumentError(names.candidates, fmt::format("'{}' is not an effect of the library ({}) nor one of the "
                                                        "scene's custom_effects",
                                                        c, fmt::join(effects::effect_types(), ", ")));
  const auto& wb = scene.wb;
  diagnosis::DiagnoseOptions o;
  o.noise_um = r.noise_um;
  o.candidates = r.candidates;
  o.own_effects = wb.scene.custom_effects;
  o.plan_layout = r.layout;
  o.chain = wb.scene.machine.chain;
  o.datum_face_z_mm = wb.scene.machine.datum_face_z_mm;
  o.on_candidate_fitted = r.on_candidate_fitted;
  o.keep_going = r.keep_going;
  if (r.scene_uncertainty) {
    o.stroke_repeatability_sd = wb.scene.machine.uncertainty.repeatability;
    o.model_uncertainty_um = diagnosis::map_sensitivity(wb, measured.points, 0, r.keep_going);
  }
  return diagnosis::diagnose(wb.setup, wb.diagnosis_model(), measured.points, wb.effect_types(), o);
}

} // namespace

CompareResult compare(const SceneInput& scene, const MeasuredInput& measured, double noise_um, const ArgumentNames& names,
                      const std::function<void()>& keep_going) {
  check_noise_um(noise_um, names.noise);
  CompareResult r;
  r.comparison =
      diagnosis::compare(scene.wb.setup, scene.wb.process(), measured.points, noise_um, measured.read, keep_going);
  r.json = report::compare_json(scene.name, measured.name, measured.points, r.comparison);
  return r;
}

DiagnoseResult diagnose(const SceneInput& scene, const MeasuredInput& measured, const DiagnoseRequest& request,
                        const std::filesystem::path& save_dir, const ArgumentNames& names) {
  DiagnoseResult r;
  r.diagnosis = run_diagnosis(scene, measured, request, names);
  const auto& d = r.diagnosis;
  r.json = diagnosis::diagnosis_json(scene.name, measured.name, d, diagnosis::mean_allowance_offset_um(scene.wb.setup.geometry()));
  if (d.chosen && !d.withheld) {
    // With the fit's uncertainties and correlation: a prediction from this scene draws the effect within them.
    const auto identified = diagnosis::identified_effects(d, *d.chosen);
    r.scene_with_effect = diagnosis::scene_text_with_effects(
        scene.text, scene.dir, save_dir, identified.effects, diagnosis::identification_comments(*d.chosen, measured.name),
        identified.uncertainties, identified.correlation, d.chosen->changes, d.chosen->change_sd,
        diagnosis::change_identification_comments(*d.chosen, measured.name), identified.draws, d.chosen->chain);
  }
  return r;
}

PlanResult plan(const SceneInput& scene, const MeasuredInput& measured, const DiagnoseRequest& request,
                const ArgumentNames& names) {
  PlanResult r;
  r.diagnosis = run_diagnosis(scene, measured, request, names);
  r.json = diagnosis::plan_json(scene.name, measured.name, r.diagnosis);
  return r;
}

} // namespace geartopo::commands
