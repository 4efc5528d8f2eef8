// geartopo Python module — series(file): a production series analysed (series::analyse_series, series::series_json),
// as `geartopo series` without its files.
#include "arguments.hpp"
#include "bindings.hpp"
#include "interrupt.hpp"
#include "json_to_python.hpp"

#include "geartopo/series/series_analysis.hpp"
#include "geartopo/workbench/workbench.hpp"

namespace py = pybind11;

namespace geartopo::python {

void bind_series(py::module_& m) {
  m.def(
      "series",
      [](const py::object& path) {
        const std::string file = path_argument(path, "file");
        nlohmann::json j;
        {
          const LibraryWork work; // Ctrl-C caught, the GIL released
          const workbench::Workbench wb(series::series_scene(file));
          const auto spec = series::load_series(file, series::strokes_per_gear(wb));
          j = series::series_json(series::analyse_series(spec, wb));
        }
        return to_python(j);
      },
      py::arg("file"),
      R"(A production series (docs/series.md), as `geartopo series` without its files: the series file (YAML,
docs/scene-format.md "Series files") read, every gear compared with the scene's model and evaluated to ISO 1328-1,
each quantity fitted across the series (thermal drift, wheel wear and re-dress, correction steps, with σ), the next
gear predicted and the class loss.

Returns the dict series.json holds: "gears" (per gear its values) and "quantities" (per quantity its values, the law
chosen with its parameters, the next gear's median and 95 % interval, the class loss).)");
}

} // namespace geartopo::python
