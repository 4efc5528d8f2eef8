#include "geartopo/pipeline/pipeline.hpp"

#include <fmt/format.h>

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/core/limits.hpp"
#include "geartopo/diagnosis/scene_writer.hpp"
#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/effects/effects_process.hpp"


namespace geartopo::pipeline {

PipelineResult run_pipeline(const workbench::Workbench& wb, const PipelineOptions& o) {
  const auto stage = [&](const std::string& name, long long flanks) {
    if (o.stage) o.stage(name, flanks);
  };
  // What the caller chose, checked before any work (core/limits.hpp; the scene's own values were checked when read).
  limits::require(limits::teeth_refusal(o.teeth, wb.setup.geometry().teeth()), "run_pipeline: teeth");
  limits::require(limits::noise_um_refusal(o.noise_um), "run_pipeline: noise_um");
  limits::require(limits::step_mm_refusal(o.step_mm), "run_pipeline: step_mm");
  if (!o.measured_file.empty()) limits::require(limits::path_refusal(o.measured_file), "run_pipeline: measured_file");
  if (o.prediction) {
    limits::require(limits::samples_refusal(o.prediction->samples, 1), "run_pipeline: prediction samples");
    limits::require(limits::synthetic_noise_um_refusal(o.prediction->probe_noise_um), "run_pipeline: probe_noise_um");
  }
  // The measurement is read before any simulation: a bad file is refused in a second, its error the first line a user
  // sees, not after minutes of work (and not after the progress lines of a slow build).
  std::optional<MeasurementResult> measured;
  measurement::ReadCounts read;
  if (!o.measured_file.empty()) {
    measured.emplace();
    measured->file = o.measured_file;
    measured->points = measurement::read_any_measurement(o.measured_file, wb.setup, &measured->warnings,
                                                         o.measurement_format, &read, o.measured_against);
  }
  PipelineResult r;
  grinding::SimulationOptions so;
  so.method = o.method;
  so.teeth = o.teeth.empty() ? wb.scene.grid.teeth : o.teeth;
  so.rows = wb.scene.grid.rows;
  so.cols = wb.scene.grid.cols;
  so.profile_points = wb.scene.grid.profile_points;
  so.helix_points = wb.scene.grid.helix_points;
  so.progress = o.progress;
  const auto& g = wb.setup.geometry();
  const long long flanks = 2LL * static_cast<long long>(so.teeth.empty() ? g.teeth() : so.teeth.size());

  stage("simulate", flanks);
  r.before = grinding::simulate_topology(wb.setup, wb.process(), so);
  r.iso_before = workbench::evaluate_iso(g, wb.setup.ranges(), r.before, o.iso);
  r.largest_before_um = grinding::largest_abs_deviation_um(r.before);
  if (o.before_ready) o.before_ready(r);
  stage("compensate", 0);
  compensation::CompensationOptions co;
  co.method = o.compensation;
  co.step_mm = o.step_mm;
  r.corrections = std::make_unique<compensation::CorrectionTable>(
      compensation::compute_corrections(wb.setup, wb.process(),
                                        {wb.machine, wb.scene.machine.datum_face_z_mm, wb.scene.machine.chain}, co));
  const compensation::CompensatedProcess corrected(wb.process(), *r.corrections);
  stage("simulate compensated", flanks);
  r.after = grinding::simulate_topology(wb.setup, corrected, so);
  r.iso_after = workbench::evaluate_iso(g, wb.setup.ranges(), r.after, o.iso);
  r.largest_after_um = grinding::largest_abs_deviation_um(r.after);
  if (o.prediction) {
    const auto [first, last] = shard_range(o.prediction->samples, o.prediction->shard, o.prediction->shards);
    stage(kPredictionStage, o.prediction->adaptive_tolerance_um > 0.0 ? o.prediction->adaptive_max_samples : last - first);
    MonteCarloOptions mc = *o.prediction;
    mc.iso = o.iso;
    r.prediction = summarise(run_monte_carlo(wb, *r.corrections, mc));
  }

  if (measured) {
    MeasurementResult& m = *measured;
    stage("compare", 0);
    m.before = diagnosis::compare(wb.setup, wb.process(), m.points, o.noise_um, read);
    stage(kDiagnoseStage, 0);
    diagnosis::DiagnoseOptions d;
    d.noise_um = m.before.noise_um;
    d.on_candidate_fitted = o.progress;
    d.own_effects = wb.scene.custom_effects;
    d.chain = wb.scene.machine.chain;
    d.datum_face_z_mm = wb.scene.machine.datum_face_z_mm;
    m.diagnosis = diagnosis::diagnose(wb.setup, wb.diagnosis_model(), m.points, wb.effect_types(), d);
    if (m.diagnosis.chosen) {
      const auto effs = workbench::make_effects(m.diagnosis.chosen->effects, m.diagnosis.chosen->changes, wb.setup,
                                                wb.scene.machine.chain, wb.scene.machine.datum_face_z_mm);
      const effects::EffectsProcess with(wb.diagnosis_model(), effs, wb.scene.machine.chain,
                                         wb.scene.machine.datum_face_z_mm);
      m.after = diagnosis::compare(wb.setup, with, m.points, m.before.noise_um, read);
    }
    r.measurement = std::move(measured);
  }
  return r;
}

PipelineResult run_pipeline(const workbench::Workbench& wb, const std::string& measured_file) {
  PipelineOptions o;
  o.measured_file = measured_file;
  return run_pipeline(wb, o);
}

std::string grid_label(const PipelineResult& r) {
  if (r.before.empty() || r.before.front().grid.empty()) return "no";
  const auto& last = r.before.front().grid.back(); // row-major: the last point has the largest row and column
  return fmt::format("{}×{}", last.row, last.col);
}

} // namespace geartopo::pipeline
