// geartopo Python module — evaluate(scene, topo): ISO 1328-1:2013 values and classes (workbench::evaluate_iso,
// report::iso_json) of a simulation, of simulate()'s arrays or of a measured traces file, as `geartopo evaluate`.
#include "arguments.hpp"
#include "bindings.hpp"
#include "interrupt.hpp"
#include "measured_input.hpp"
#include "named_arguments.hpp"
#include "json_to_python.hpp"
#include "numpy_columns.hpp"
#include "py_scene.hpp"
#include "python_progress.hpp"

#include "geartopo/commands/machine_values.hpp"
#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/report/iso_report.hpp"

#include <stdexcept>

namespace py = pybind11;

namespace geartopo::python {

void bind_evaluate(py::module_& m) {
  m.def(
      "evaluate",
      [](const SceneArg& scene, const py::object& topo, const TextArg& method_arg, const TextArg& direction,
         const TextArg& slope_sign, const py::object& progress, const py::object& against_arg) {
        const auto& wb = *scene_argument(scene, "scene").wb;
        const auto against = measured_against_argument(against_arg);
        if (against != measurement::MeasuredAgainst::as_file && (topo.is_none() || py::isinstance<py::dict>(topo)))
          throw py::value_error("measured_against: is for a measured traces file (topo=path): arrays and the "
                                "simulation say their design themselves");
        const std::string method = text_argument(method_arg, "method");
        const workbench::IsoOptions iso =
            iso_arguments(text_argument(direction, "iso_direction"), text_argument(slope_sign, "helix_slope_sign"));
        std::vector<grinding::FlankTopology> flanks;
        if (topo.is_none()) { // as `geartopo evaluate`: every tooth (pitch and runout need them), traces only
          grinding::SimulationOptions so;
          so.method = method_argument(method);
          so.profile_points = wb.scene.grid.profile_points;
          so.helix_points = wb.scene.grid.helix_points;
          so.progress = progress_function(progress);
          so.keep_going = interrupt_check();
          const LibraryWork work; // Ctrl-C caught, the GIL released
          flanks = grinding::simulate_topology(wb.setup, wb.process(), so);
        } else if (py::isinstance<py::dict>(topo)) { // simulate()'s or synth()'s arrays
          flanks = topology_from_columns(topo.cast<py::dict>(), "topo");
        } else { // a measured traces file
          const std::string file = path_argument(topo, "topo");
          auto traces = measurement::read_any_traces(file, wb.setup, {}, against);
          if (!traces.warnings.empty()) {
            const auto warn = py::module_::import("warnings").attr("warn");
            for (const auto& w : traces.warnings) warn(w);
          }
          workbench::IsoResult from_file; // a trace the evaluation refuses is named with the file and its line
          {
            const LibraryWork work; // Ctrl-C caught, the GIL released
            from_file = commands::evaluate_measured_traces(wb, traces, file, iso);
          }
          return to_python(report::iso_json(from_file));
        }
        workbench::IsoResult result;
        {
          const LibraryWork work; // Ctrl-C caught, the GIL released
          result = workbench::evaluate_iso(wb.setup.geometry(), wb.setup.ranges(), flanks, iso);
        }
        return to_python(report::iso_json(result));
      },
      py::arg("scene"), py::arg("topo") = py::none(), py::arg("method") = "exact",
      py::arg("iso_direction") = "transverse", py::arg("helix_slope_sign") = "helix-angle",
      py::arg("progress") = py::none(), py::arg("measured_against") = py::none(),
      R"(ISO 1328-1:2013 deviations (µm) and flank tolerance classes, as `geartopo evaluate`.

topo: None (simulate every tooth with `method`, as the CLI), simulate()'s dict (its "traces" are evaluated; pitch
and runout need every tooth), a traces dict (synth(format="traces")), or the path of a measured traces file (traces
CSV or Klingelnberg export).
measured_against: for a traces file without a design_um column, "design" (deviations from the drawing) or
"involute", as the CLI's --measured-against; None: the bare involute, with a warning on a designed gear.
iso_direction: "transverse" (the standard's) or "normal"; helix_slope_sign: "helix-angle" or "rise-towards-plus-z".

Returns the dict iso1328.json holds under "before": per flank the trace values, pitch, runout and classes.)");
}

} // namespace geartopo::python
