// geartopo Python module — series(file): a production series analysed (series::analyse_series, series::series_json),
// as `geartopo series` without its files.
#include "arguments.hpp"
#include "bindings.hpp"
#include "interrupt.hpp"
#include "json_to_python.hpp"
#include "named_arguments.hpp"

#include "geartopo/scene/scene.hpp"
#include "geartopo/series/series_analysis.hpp"
#include "geartopo/workbench/workbench.hpp"

namespace py = pybind11;

namespace geartopo::python {

void bind_series(py::module_& m) {
  m.def(
      "series",
      [](const py::object& path, const FlagArg& diagnose) {
        const std::string file = path_argument(path, "file");
        const bool diagnose_gears = flag_argument(diagnose, "diagnose_gears");
        nlohmann::json j;
        {
          const LibraryWork work; // Ctrl-C caught, the GIL released
          const workbench::Workbench wb(scene::load_scene(series::series_scene(file)), interrupt_check());
          const auto spec = series::load_series(file, series::strokes_per_gear(wb));
          series::SeriesOptions options;
          options.keep_going = interrupt_check(); // before each gear, between its steps, within an export's reading
          options.diagnose_gears = diagnose_gears; // or the series file's diagnose_gears: true
          j = series::series_json(series::analyse_series(spec, wb, options));
        }
        return to_python(j);
      },
      py::arg("file"), py::arg("diagnose_gears") = false,
      R"(A production series (docs/series.md), as `geartopo series` without its files: the series file (YAML,
docs/scene-format.md "Series files") read, every gear compared with the scene's model and evaluated to ISO 1328-1,
each quantity fitted across the series (thermal drift, wheel wear and re-dress, correction steps, with σ), the next
gear predicted and the class loss.

diagnose_gears: each gear's measurement also through diagnose's pipeline (its within-job effects, as
`geartopo diagnose`), as the series file's `diagnose_gears: true` asks: each gear's "diagnosis" (verdict, chosen).

Returns the dict series.json holds: "gears" (per gear its values) and "quantities" (per quantity its values, the law
chosen with its parameters, the next gear's median and 95 % interval, the class loss).)");
}

} // namespace geartopo::python
