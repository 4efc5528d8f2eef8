// geartopo Python module — simulate(scene, …): grinding::simulate_topology with the options `geartopo simulate`
// gives it, the result as topology.csv's and traces.csv's columns.
#include "arguments.hpp"
#include "bindings.hpp"
#include "interrupt.hpp"
#include "named_arguments.hpp"
#include "numpy_columns.hpp"
#include "py_scene.hpp"
#include "python_progress.hpp"

#include <pybind11/stl.h>

#include <fmt/format.h>

#include <stdexcept>

namespace py = pybind11;

namespace geartopo::python {

void bind_simulate(py::module_& m) {
  m.def(
      "simulate",
      [](const SceneArg& scene, const py::object& teeth, const TextArg& method_arg, const py::object& dense,
         const py::object& progress, const WholeArg& thread_count) {
        const auto& wb = *scene_argument(scene, "scene").wb;
        const std::string method = text_argument(method_arg, "method");
        const int threads = static_cast<int>(whole_argument(thread_count, "threads", 0, kMaxThreads));
        grinding::SimulationOptions so = workbench::scene_simulation(wb.scene.grid);
        so.method = method_argument(method);
        so.teeth = teeth_argument(teeth, wb.setup.geometry().teeth(), wb.scene.grid.teeth);
        if (!dense.is_none()) {
          std::tie(so.dense_rows, so.dense_cols) = grid_argument(dense, "dense");
        }
        so.threads = threads;
        so.progress = progress_function(progress);
        so.keep_going = interrupt_check();
        std::vector<grinding::FlankTopology> topo;
        {
          const LibraryWork work; // Ctrl-C caught, the GIL released
          topo = grinding::simulate_topology(wb.setup, wb.process(), so);
        }
        py::dict out = topology_columns(topo, grinding::GridKind::Topology);
        out["traces"] = traces_columns(topo);
        if (so.dense_rows > 0) out["dense"] = topology_columns(topo, grinding::GridKind::Dense);
        out["method"] = method;
        out["rows"] = so.rows;
        out["cols"] = so.cols;
        return out;
      },
      py::arg("scene"), py::arg("teeth") = py::none(), py::arg("method") = "exact", py::arg("dense") = py::none(),
      py::arg("progress") = py::none(), py::arg("threads") = 0,
      R"(Line-contact grinding with the scene's machine errors and effects, as `geartopo simulate`.

teeth: None (the scene's measurement.teeth, else all), "all", or tooth numbers such as [1, 18].
method: "exact" (envelope of the actual wheel poses) or "linear" (first order).
dense: None (the scene's) or (rows, cols) of an extra dense grid per flank.
progress: None or a callable(flanks_done, flanks) called from the work (with the GIL).
threads: 0 for all hardware threads (results do not depend on it).

Returns a dict of numpy arrays, one row per grid point, the columns of topology.csv: tooth, flank, row, col,
diameter_mm, z_mm, deviation_um, design_um (plus roll_length_mm); "traces": the columns of traces.csv (tooth, flank,
trace, roll_length_mm, diameter_mm, z_mm, deviation_um, design_um); "dense": the dense grid's, when there is one;
"method", "rows", "cols". Deviations in µm along the flank normal, plus material positive.)");
}

} // namespace geartopo::python
