// geartopo Python module — compensate(scene, …): the axis corrections, the gear before and the nominal after-state,
// and the predicted after-state as a distribution — the library calls of `geartopo compensate` (its cycle table,
// ISG table and shards stay with the CLI).
#include "arguments.hpp"
#include "bindings.hpp"
#include "interrupt.hpp"
#include "named_arguments.hpp"
#include "json_to_python.hpp"
#include "numpy_columns.hpp"
#include "py_scene.hpp"
#include "python_progress.hpp"

#include "geartopo/commands/limits.hpp"
#include "geartopo/compensation/compensator.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/report/improvement.hpp"
#include "geartopo/report/iso_report.hpp"
#include "geartopo/report/prediction_report.hpp"

#include <fmt/format.h>

#include <limits>
#include <optional>
#include <stdexcept>

namespace py = pybind11;

namespace geartopo::python {
namespace {

/// corrections.csv's columns (CorrectionTable::write_csv), named as its header names them (the scene's chain's axis
/// letters, e.g. U_mm and dU_um for a radial slide called U): axes in mm and deg, corrections in µm and µrad.
py::dict correction_columns(const compensation::CorrectionTable& table) {
  const auto& rows = table.rows();
  const std::size_t n = rows.size();
  auto space = new_column<int>(n);
  auto within = new_column<bool>(n);
  std::vector<py::array_t<double>> v;
  const std::vector<std::string> header = table.column_names(); // space, the 12 below, within_strokes
  const std::vector<std::string> names(header.begin() + 1, header.end() - 1);
  for (std::size_t c = 0; c < names.size(); ++c) v.push_back(new_column<double>(n));
  for (std::size_t k = 0; k < n; ++k) {
    const auto i = static_cast<py::ssize_t>(k);
    const auto& r = rows[k];
    const auto& q = r.machine_axes;
    const auto& c = r.correction;
    space.mutable_at(i) = r.space;
    within.mutable_at(i) = r.within_strokes;
    const double values[] = {r.z_stroke_mm, r.time_s, q.x, q.y, q.z, q.a * units::kDegPerRad, q.c * units::kDegPerRad,
                             units::um_from_mm(c(0)), units::um_from_mm(c(1)), units::um_from_mm(c(2)),
                             units::urad_from_rad(c(3)), units::urad_from_rad(c(4))};
    for (std::size_t col = 0; col < v.size(); ++col) v[col].mutable_at(i) = values[col];
  }
  py::dict out;
  out["space"] = space;
  for (std::size_t col = 0; col < v.size(); ++col) out[py::str(names[col])] = v[col];
  out["within_strokes"] = within;
  return out;
}

py::dict topology_dict(const std::vector<grinding::FlankTopology>& topo) {
  py::dict out = topology_columns(topo, grinding::GridKind::Topology);
  out["traces"] = traces_columns(topo);
  return out;
}

compensation::Method compensation_method(const std::string& method) {
  if (method == "paper") return compensation::Method::Paper;
  if (method == "flank") return compensation::Method::Flank;
  if (method == "cycle") return compensation::Method::Cycle;
  throw std::invalid_argument(fmt::format("method: '{}' is not paper, flank or cycle", method));
}

} // namespace

void bind_compensate(py::module_& m) {
  m.def(
      "compensate",
      [](const SceneArg& scene, const TextArg& method_arg, const RealArg& step, const WholeArg& sample_count,
         const WholeArg& seed_arg, const TextArg& direction, const TextArg& slope_sign, const RealArg& probe_noise,
         const FlagArg& exact, const py::object& progress, const WholeArg& thread_count) {
        const auto& wb = *scene_argument(scene, "scene").wb;
        const std::string method = text_argument(method_arg, "method");
        const double step_mm = real_argument(step, "step_mm");
        const long long samples = whole_argument(sample_count, "samples", std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max());
        const std::uint64_t seed = seed_argument(seed_arg, "seed");
        const std::string iso_direction = text_argument(direction, "iso_direction");
        const std::string helix_slope_sign = text_argument(slope_sign, "helix_slope_sign");
        const double probe_noise_um = real_argument(probe_noise, "probe_noise_um");
        const bool exact_samples = flag_argument(exact, "exact_samples");
        const int threads = static_cast<int>(whole_argument(thread_count, "threads", 0, kMaxThreads));
        compensation::CompensationOptions co;
        co.method = compensation_method(method);
        if (const auto refusal = limits::step_mm_refusal(step_mm)) throw std::invalid_argument("step_mm: " + *refusal);
        co.step_mm = step_mm;
        if (co.method == compensation::Method::Paper && wb.design_motion) // as the CLI's --method paper
          throw std::invalid_argument("method: paper drives the wheel to its nominal pose and would grind away the "
                                      "drawing's helix modifications (gear.modifications): use flank or cycle, which "
                                      "correct towards the design");
        commands::check_samples(samples, "samples"); // the CLI's --samples bound
        commands::check_synthetic_noise_um(probe_noise_um, "probe_noise_um");
        grinding::SimulationOptions so;
        so.profile_points = wb.scene.grid.profile_points;
        so.helix_points = wb.scene.grid.helix_points;
        so.rows = wb.scene.grid.rows;
        so.cols = wb.scene.grid.cols;
        so.threads = threads;
        so.keep_going = interrupt_check(); // the simulations before and after report no progress
        pipeline::MonteCarloOptions mc;
        mc.samples = samples;
        mc.seed = seed;
        mc.iso = iso_arguments(iso_direction, helix_slope_sign);
        mc.probe_noise_um = probe_noise_um;
        mc.sampling = exact_samples ? pipeline::Sampling::Exact : pipeline::Sampling::Checked;
        mc.threads = threads;
        mc.on_sample_done = progress_function(progress);

        std::vector<grinding::FlankTopology> before, after;
        std::optional<compensation::CorrectionTable> table;
        std::optional<pipeline::MonteCarloSummary> prediction;
        workbench::IsoResult iso_b, iso_a;
        {
          const LibraryWork work; // Ctrl-C caught, the GIL released
          before = grinding::simulate_topology(wb.setup, wb.process(), so);
          table = compensation::compute_corrections(
              wb.setup, wb.process(), {wb.machine, wb.scene.machine.datum_face_z_mm, wb.scene.machine.chain}, co);
          const compensation::CompensatedProcess corrected(wb.process(), *table);
          after = grinding::simulate_topology(wb.setup, corrected, so);
          if (samples > 0) prediction = pipeline::summarise(pipeline::run_monte_carlo(wb, *table, mc));
          iso_b = workbench::evaluate_iso(wb.setup.geometry(), wb.setup.ranges(), before, mc.iso);
          iso_a = workbench::evaluate_iso(wb.setup.geometry(), wb.setup.ranges(), after, mc.iso);
        }
        py::dict out;
        out["corrections"] = correction_columns(*table);
        out["before"] = topology_dict(before);
        out["nominal_after"] = topology_dict(after);
        py::dict iso;
        iso["before"] = to_python(report::iso_json(iso_b));
        iso["nominal_after"] = to_python(report::iso_json(iso_a));
        out["iso1328"] = iso;
        py::dict largest;
        largest["before"] = grinding::largest_abs_deviation_um(before);
        largest["nominal_after"] = grinding::largest_abs_deviation_um(after);
        out["largest_abs_deviation_um"] = largest;
        out["rows_outside_strokes"] = table->rows_outside_strokes();
        out["prediction"] = prediction ? to_python(report::prediction_json(*prediction)) : py::none();
        out["improvement"] = prediction ? to_python(report::improvement_json(*prediction)) : py::none();
        return out;
      },
      py::arg("scene"), py::arg("method") = "flank", py::arg("step_mm") = 2.0, py::arg("samples") = 40,
      py::arg("seed") = 1, py::arg("iso_direction") = "transverse", py::arg("helix_slope_sign") = "helix-angle",
      py::arg("probe_noise_um") = 0.0, py::arg("exact_samples") = false, py::arg("progress") = py::none(),
      py::arg("threads") = 0,
      R"(Axis corrections along the wheel path and the gear before and after, as `geartopo compensate`.

method: "flank" (default), "paper" or "cycle"; step_mm: the table's spacing along each stroke.
samples, seed: the Monte Carlo prediction of the after-state (0: none); probe_noise_um, exact_samples as the CLI's
--probe-noise-um, --exact-samples. progress: None or a callable(samples_done, samples) (with the GIL).

Returns a dict: "corrections" (corrections.csv's columns as arrays), "before" and "nominal_after" (the topology and
"traces" columns of topology_before/after.csv; nominal: the model corrected by itself, ≈ 0 by construction),
"iso1328" ({"before", "nominal_after"}: iso1328.json's sections), "largest_abs_deviation_um", "rows_outside_strokes",
"prediction" (prediction.json's content: the predicted distribution before and after) and "improvement", both None
without samples.)");
}

} // namespace geartopo::python
