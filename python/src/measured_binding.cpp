// geartopo Python module — compare, diagnose, plan: a measurement against the scene's model, with the library calls
// of `geartopo compare`, `diagnose` and `plan` and their JSON files' content (report/measurement_report.hpp).
#include "arguments.hpp"
#include "bindings.hpp"
#include "interrupt.hpp"
#include "json_to_python.hpp"
#include "measured_input.hpp"
#include "named_arguments.hpp"
#include "numpy_columns.hpp"
#include "py_scene.hpp"
#include "python_progress.hpp"

#include "geartopo/commands/limits.hpp"
#include "geartopo/diagnosis/diagnosis_json.hpp"
#include "geartopo/commands/measured.hpp"
#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/identified_effects.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/diagnosis/scene_writer.hpp"
#include "geartopo/diagnosis/stroke_scatter.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/report/measurement_report.hpp"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <optional>
#include <stdexcept>

namespace py = pybind11;

namespace geartopo::python {
namespace {

/// residuals.csv's columns (report::write_residuals_csv).
py::dict residual_columns(const std::vector<measurement::MeasuredPoint>& pts, const diagnosis::Comparison& c) {
  const std::size_t n = pts.size();
  auto tooth = new_column<int>(n), row = new_column<int>(n), col = new_column<int>(n), line = new_column<int>(n);
  auto id = new_column<std::int64_t>(n);
  auto d = new_column<double>(n), z = new_column<double>(n), measured = new_column<double>(n), model = new_column<double>(n),
       residual = new_column<double>(n), design = new_column<double>(n);
  WordColumn flank(n, kFlankWidth);
  for (std::size_t k = 0; k < n; ++k) {
    const auto i = static_cast<py::ssize_t>(k);
    const auto& p = pts[k];
    tooth.mutable_at(i) = p.tooth, row.mutable_at(i) = p.row, col.mutable_at(i) = p.col, line.mutable_at(i) = p.line;
    id.mutable_at(i) = p.id;
    d.mutable_at(i) = p.diameter_mm, z.mutable_at(i) = p.z_mm, measured.mutable_at(i) = p.deviation_um;
    model.mutable_at(i) = c.model_um[k], residual.mutable_at(i) = c.residual_um[k], design.mutable_at(i) = p.design_um;
    flank.set(k, to_string(p.flank));
  }
  py::dict out;
  out["tooth"] = tooth;
  out["flank"] = flank.array();
  out["row"] = row;
  out["col"] = col;
  out["diameter_mm"] = d;
  out["z_mm"] = z;
  out["measured_um"] = measured;
  out["model_um"] = model;
  out["residual_um"] = residual;
  out["source_line"] = line;
  out["point_id"] = id;
  out["design_um"] = design;
  return out;
}

commands::SceneInput scene_input(const PyScene& s) { return {*s.wb, s.source, s.text, s.dir}; }

commands::DiagnoseRequest request_of(double noise_um, const std::vector<std::string>& candidates, bool scene_uncertainty,
                                     const py::object& progress) {
  commands::DiagnoseRequest r;
  r.noise_um = noise_um;
  r.candidates = candidates;
  r.scene_uncertainty = scene_uncertainty;
  r.on_candidate_fitted = progress_function(progress);
  r.keep_going = interrupt_check(); // a fit on a large measurement takes seconds between progress reports
  return r;
}

} // namespace

void bind_measured(py::module_& m) {
  m.def(
      "compare",
      [](const SceneArg& scene, const py::object& measured, const RealArg& noise, const py::object& against) {
        const PyScene& s = scene_argument(scene, "scene");
        const double noise_um = real_argument(noise, "noise_um");
        commands::check_noise_um(noise_um, "noise_um"); // before reading the measurement
        std::string name;
        const auto pts = measured_points(s, measured, name, measured_against_argument(against));
        std::optional<commands::CompareResult> r;
        {
          const LibraryWork work; // Ctrl-C caught, the GIL released
          r = commands::compare(scene_input(s), {pts, name, {}}, noise_um, {}, interrupt_check());
        }
        py::dict out = to_python(r->json).cast<py::dict>();
        out["residuals"] = residual_columns(pts, r->comparison);
        return out;
      },
      py::arg("scene"), py::arg("measured"), py::arg("noise_um") = 0.0, py::arg("measured_against") = py::none(),
      R"(Measured − model at every measured point, as `geartopo compare`.

measured: a measurement file's path (topology CSV, traces CSV, point cloud, Klingelnberg export) or a dict of arrays
with topology.csv's columns (synth()'s result). noise_um: the probe noise σ (0: estimated).
measured_against: what a measurement without a design_um column is measured from, as --measured-against: "design"
(the drawing, as a measuring machine that evaluates against it writes), "involute", or None (as the file says; the
scene's measurement.measured_against for its own file; compare.json's reference_in_doubt says when the residual looks
like minus the drawing).
Returns compare.json's content, plus "residuals": residuals.csv's columns as arrays.)");

  m.def(
      "diagnose",
      [](const SceneArg& scene, const py::object& measured, const RealArg& noise,
         const TextListArg& candidate_list, const FlagArg& uncertainty, const py::object& progress,
         const py::object& yaml_dir, const py::object& against) {
        const PyScene& s = scene_argument(scene, "scene");
        const double noise_um = real_argument(noise, "noise_um");
        commands::check_noise_um(noise_um, "noise_um");
        const auto candidates = text_list_argument(candidate_list, "candidates");
        const bool scene_uncertainty = flag_argument(uncertainty, "scene_uncertainty");
        std::string name;
        const auto pts = measured_points(s, measured, name, measured_against_argument(against));
        const auto request = request_of(noise_um, candidates, scene_uncertainty, progress);
        const std::filesystem::path to = yaml_dir.is_none() ? s.dir : std::filesystem::path(path_argument(yaml_dir, "yaml_dir"));
        std::optional<commands::DiagnoseResult> r;
        {
          const LibraryWork work; // Ctrl-C caught, the GIL released
          r = commands::diagnose(scene_input(s), {pts, name, {}}, request, to);
        }
        py::dict out = to_python(r->json).cast<py::dict>();
        out["scene_with_effect_yaml"] = r->scene_with_effect ? py::cast(*r->scene_with_effect) : py::none();
        return out;
      },
      py::arg("scene"), py::arg("measured"), py::arg("noise_um") = 0.0,
      py::arg("candidates") = std::vector<std::string>{}, py::arg("scene_uncertainty") = false,
      py::arg("progress") = py::none(), py::arg("yaml_dir") = py::none(), py::arg("measured_against") = py::none(),
      R"(Which physical effect the model is missing, as `geartopo diagnose`.

measured, measured_against: as for compare. candidates: effect types to try (default: every library effect not in the scene).
scene_uncertainty: fit with the scene's declared uncertainties (generalised least squares).
progress: None or a callable(fits_done, fits) (with the GIL).
yaml_dir: the folder the completed scene will be saved in, its relative paths rewritten for it (default: the
scene's own folder).
Returns diagnosis.json's content, plus "scene_with_effect_yaml": the scene's text with the chosen effect added (the
file `geartopo diagnose` writes), or None when nothing is chosen or it is withheld (see "withheld").)");

  m.def(
      "plan",
      [](const SceneArg& scene, const py::object& measured, const RealArg& noise, const py::object& progress,
         const py::object& against) {
        const PyScene& s = scene_argument(scene, "scene");
        const double noise_um = real_argument(noise, "noise_um");
        commands::check_noise_um(noise_um, "noise_um");
        std::string name;
        const auto pts = measured_points(s, measured, name, measured_against_argument(against));
        const auto request = request_of(noise_um, {}, false, progress);
        std::optional<commands::PlanResult> r;
        {
          const LibraryWork work; // Ctrl-C caught, the GIL released
          r = commands::plan(scene_input(s), {pts, name, {}}, request);
        }
        return to_python(r->json);
      },
      py::arg("scene"), py::arg("measured"), py::arg("noise_um") = 0.0, py::arg("progress") = py::none(),
      py::arg("measured_against") = py::none(),
      R"(What to measure next when explanations are within ΔBIC 10 of each other, as `geartopo plan`.
measured, measured_against: as for compare.
Returns plan.json's content: chosen, ambiguous, plan (None when not ambiguous), verdict.)");
}

} // namespace geartopo::python
