// One gear of a series: its residual against the model it was ground with, its ISO 1328-1 values (series_analysis.hpp).
#include "geartopo/series/series_analysis.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/compensation/correction_table.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/measurement/any_measurement.hpp"

#include <fmt/format.h>

#include <cmath>

namespace geartopo::series {
namespace {

/// The mean of a process variable over the compared points (residual_follows.hpp), nullopt when it did not vary.
std::optional<double> mean_of(const diagnosis::ResidualFollows& f, const std::string& variable) {
  for (const auto& d : f.variables)
    if (d.variable == variable && !d.values.empty()) {
      double s = 0.0;
      for (double v : d.values) s += v;
      return s / static_cast<double>(d.values.size());
    }
  return std::nullopt;
}

/// The traces of the file for the ISO evaluator, or why there are none (a grid or a cloud holds no traces).
std::optional<workbench::IsoResult> iso_of(const workbench::Workbench& wb, const SeriesGear& gear,
                                           const workbench::IsoOptions& options, const measurement::KlingelnbergOptions& mka,
                                           std::string& note) {
  measurement::MeasuredTraces traces;
  try {
    traces = measurement::read_any_traces(gear.measurement.string(), wb.setup, mka);
  } catch (const InputError&) {
    // Not a traces CSV or an export: the file was read as measured points already, so it is a grid or a cloud.
    note = fmt::format("{}: no profile and helix traces (a grid or a point cloud): ISO 1328-1 values not evaluated",
                       gear.measurement.string());
    return std::nullopt;
  }
  return workbench::evaluate_iso(wb.setup.geometry(), wb.setup.ranges(), traces.flanks, options);
}

/// The gear's measurement through diagnose's pipeline, with the options `geartopo diagnose` gives it by default
/// (noise estimated, every library effect and the scene's own), against `model`: what the gear was ground with.
diagnosis::Diagnosis diagnose_gear(const workbench::Workbench& wb, const grinding::GrindingProcess& model,
                                   const std::vector<measurement::MeasuredPoint>& points, const SeriesOptions& options) {
  diagnosis::DiagnoseOptions o;
  o.own_effects = wb.scene.custom_effects;
  o.chain = wb.scene.machine.chain; // the chain's own error Jacobian for its machine elements
  o.datum_face_z_mm = wb.scene.machine.datum_face_z_mm;
  o.keep_going = options.keep_going;
  auto d = diagnosis::diagnose(wb.setup, model, points, wb.effect_types(), o);
  d.residual_before_um.clear(), d.residual_before_um.shrink_to_fit(); // per point: not kept for a whole series
  d.residual_after_um.clear(), d.residual_after_um.shrink_to_fit();
  return d;
}

} // namespace

GearValues gear_values(const workbench::Workbench& wb, const SeriesGear& gear, const workbench::IsoOptions& iso,
                       const SeriesOptions& options) {
  const auto keep_going = [&options] { if (options.keep_going) options.keep_going(); };
  measurement::KlingelnbergOptions mka; // the default reader options, with the Ctrl-C check
  mka.keep_going = options.keep_going;
  GearValues v;
  v.gear = gear;
  keep_going();
  const auto points = measurement::read_any_measurement(gear.measurement.string(), wb.setup, nullptr, mka);
  keep_going();
  // Against the scene's model as it is, without the gear's corrections: a change of corrections then shows as a step
  // of the series, beside what the model expects of it (correction_effect_um).
  const diagnosis::Comparison c = diagnosis::compare(wb.setup, wb.process(), points, 0.0, {}, options.keep_going);
  keep_going();
  std::vector<double> corrected_model;
  std::optional<compensation::CorrectionTable> table;
  if (!gear.corrections.empty()) {
    table = compensation::CorrectionTable::read_csv(gear.corrections,
                                                    {wb.scene.machine.chain, wb.scene.machine.datum_face_z_mm});
    const compensation::CompensatedProcess corrected(wb.process(), *table);
    corrected_model = diagnosis::predict(wb.setup, corrected, points, grinding::Method::Exact, 0, options.keep_going);
  }
  if (options.diagnose_gears) { // within the job: against what it was ground with, its corrections included
    keep_going();
    if (table) v.diagnosis = diagnose_gear(wb, compensation::CompensatedProcess(wb.diagnosis_model(), *table), points, options);
    else v.diagnosis = diagnose_gear(wb, wb.diagnosis_model(), points, options);
  }
  double sum[2] = {0.0, 0.0}, effect[2] = {0.0, 0.0}, squares = 0.0;
  for (const auto& idx : c.flank_point_index)
    for (const size_t i : idx) {
      const int side = points[i].flank == Flank::Left ? 0 : 1;
      sum[side] += c.residual_um[i];
      if (!corrected_model.empty()) effect[side] += corrected_model[i] - c.model_um[i];
      ++v.points[side];
      squares += c.residual_um[i] * c.residual_um[i];
    }
  const std::size_t used = v.points[0] + v.points[1];
  if (used == 0)
    throw InputError(gear.measurement.string(), 0, 0, "", "no measured point inside the evaluation ranges");
  for (int s = 0; s < 2; ++s) {
    v.mean_residual_um[s] = v.points[s] ? sum[s] / static_cast<double>(v.points[s]) : std::nan("");
    v.correction_effect_um[s] = v.points[s] ? effect[s] / static_cast<double>(v.points[s]) : 0.0;
  }
  v.rms_residual_um = std::sqrt(squares / static_cast<double>(used));
  v.noise_um = c.noise_um;
  v.mean_grinding_time_s = 60.0 * mean_of(c.follows, "grinding time").value_or(0.0);
  v.mean_stroke = mean_of(c.follows, "stroke order").value_or(1.0) - 1.0;
  keep_going();
  v.iso = iso_of(wb, gear, iso, mka, v.iso_note);
  return v;
}

} // namespace geartopo::series
