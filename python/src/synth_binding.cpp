// geartopo Python module — synth(truth, …): a synthetic measurement of a gear ground on a truth scene, the library
// calls of `geartopo synth` (diagnosis::synthesize / synthesize_traces, pipeline::synth_corrections).
#include "arguments.hpp"
#include "bindings.hpp"
#include "interrupt.hpp"
#include "named_arguments.hpp"
#include "numpy_columns.hpp"
#include "py_scene.hpp"

#include "geartopo/commands/limits.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/pipeline/synth_corrections.hpp"

#include <pybind11/stl.h>

#include <fmt/format.h>

#include <optional>
#include <stdexcept>

namespace py = pybind11;

namespace geartopo::python {

void bind_synth(py::module_& m) {
  m.def(
      "synth",
      [](const SceneArg& truth, const py::object& teeth, const RealArg& noise, const WholeArg& seed_arg,
         const TextArg& format_arg, const FlagArg& scatter, const py::object& corrections) {
        const auto& wb = *scene_argument(truth, "truth").wb;
        const double noise_um = real_argument(noise, "noise_um");
        const std::uint64_t seed = seed_argument(seed_arg, "seed");
        const std::string format = text_argument(format_arg, "format");
        const bool stroke_scatter = flag_argument(scatter, "stroke_scatter");
        if (format != "csv" && format != "traces")
          throw std::invalid_argument(fmt::format("format: '{}' is not csv or traces (a Klingelnberg export: the CLI's "
                                                  "--format klingelnberg)",
                                                  format));
        commands::check_synthetic_noise_um(noise_um, "noise_um");
        diagnosis::SynthOptions so;
        so.teeth = teeth_argument(teeth, wb.setup.geometry().teeth(), {1, 18});
        so.rows = wb.scene.grid.rows;
        so.cols = wb.scene.grid.cols;
        so.noise_um = noise_um;
        so.seed = seed;
        so.keep_going = interrupt_check(); // a fine grid's flank takes minutes
        const std::string corrections_file = corrections.is_none() ? std::string() : path_argument(corrections, "corrections");
        const LibraryWork work; // Ctrl-C caught, the GIL released
        const auto table = pipeline::synth_corrections(wb, corrections_file, stroke_scatter, seed);
        std::optional<compensation::CompensatedProcess> corrected;
        if (table) corrected.emplace(wb.process(), *table);
        const grinding::GrindingProcess& process =
            corrected ? static_cast<const grinding::GrindingProcess&>(*corrected) : wb.process();
        if (format == "traces") {
          const auto topo = diagnosis::synthesize_traces(wb.setup, process, so, wb.scene.grid.profile_points,
                                                         wb.scene.grid.helix_points);
          const py::gil_scoped_acquire gil;
          return traces_columns(topo);
        }
        const auto rows = diagnosis::synthesize(wb.setup, process, so);
        const py::gil_scoped_acquire gil;
        return topology_row_columns(rows);
      },
      py::arg("truth"), py::arg("teeth") = std::vector<int>{1, 18}, py::arg("noise_um") = 0.5, py::arg("seed") = 1,
      py::arg("format") = "csv", py::arg("stroke_scatter") = false, py::arg("corrections") = py::none(),
      R"(A synthetic measurement of a gear ground on a truth scene, with Gaussian probe noise, as `geartopo synth`.

teeth: the measured teeth ([1, 18] by default, or "all"); noise_um: the probe noise σ; seed: the random seed.
format: "csv" (the scene's grid: measured.csv's columns tooth, flank, row, col, diameter_mm, z_mm, deviation_um,
design_um) or "traces" (one profile and one helix trace per flank: traces.csv's columns, for evaluate()).
stroke_scatter: each stroke's commands off by a draw of machine.repeatability; corrections: the path of a
compensate run's corrections.csv to grind with (rounded to machine.resolution).
Returns a dict of numpy arrays, accepted as `measured` by compare, diagnose and plan.)");
}

} // namespace geartopo::python
