// geartopo Python module — machine_values(scene, export, values): the measuring machine's own evaluation beside
// geartopo's evaluation of the same traces, as `geartopo evaluate --traces EXPORT.mka [--machine-values EXPORT.mew]`
// writes it into iso1328.json: the same calls (commands/machine_values.hpp).
#include "arguments.hpp"
#include "bindings.hpp"
#include "interrupt.hpp"
#include "named_arguments.hpp"
#include "json_to_python.hpp"
#include "py_scene.hpp"

#include "geartopo/commands/machine_values.hpp"
#include "geartopo/measurement/klingelnberg.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>

namespace py = pybind11;

namespace geartopo::python {

void bind_machine_values(py::module_& m) {
  m.def(
      "machine_values",
      [](const SceneArg& scene, const py::object& export_path, const py::object& values_path, const TextArg& direction,
         const TextArg& slope_sign) {
        const auto& wb = *scene_argument(scene, "scene").wb;
        const workbench::IsoOptions iso =
            iso_arguments(text_argument(direction, "iso_direction"), text_argument(slope_sign, "helix_slope_sign"));
        const std::string file = path_argument(export_path, "export");
        const std::string values_file = values_path.is_none() ? std::string() : path_argument(values_path, "values");
        {
          std::ifstream in(file, std::ios::binary); // unreadable: the reader below says why
          if (in && !measurement::looks_like_klingelnberg(in))
            throw std::invalid_argument(file + " is not a Klingelnberg export: the machine's values are compared with "
                                               "geartopo's evaluation of an export's curves (.mka)");
        }
        commands::MachineValuesResult compared;
        std::vector<std::string> warnings;
        {
          const LibraryWork work; // Ctrl-C caught, the GIL released
          measurement::KlingelnbergOptions mka; // the default reader options
          mka.keep_going = interrupt_check();   // a 64 MB export takes seconds to read
          const auto read = commands::read_traces_with_machine_values(wb, file, values_file, mka, {});
          warnings = read.warnings;
          const workbench::IsoResult result = commands::evaluate_measured_traces(wb, read.traces, file, iso);
          compared = commands::machine_values(wb, read, result);
        }
        if (!warnings.empty()) {
          const auto warn = py::module_::import("warnings").attr("warn");
          for (const auto& w : warnings) warn(w);
        }
        return to_python(compared.json);
      },
      py::arg("scene"), py::arg("export"), py::arg("values") = py::none(), py::arg("iso_direction") = "transverse",
      py::arg("helix_slope_sign") = "helix-angle",
      R"(The measuring machine's own evaluation beside geartopo's evaluation of the same traces, as
`geartopo evaluate SCENE --traces EXPORT --machine-values VALUES` writes it into iso1328.json.

export: a Klingelnberg export's path (.mka, read with the default reader options); anything else is a ValueError.
values: the machine's value file (.mew) or None. iso_direction: "transverse" or "normal"; helix_slope_sign:
"helix-angle" or "rise-towards-plus-z" (how geartopo evaluates the traces).

Returns a dict with "machine_pitch_table" when the export has a pitch table (f_p, F_p in µm per tooth and flank
beside geartopo's) and "machine_flank_values" when `values` is given (f_Hα … F_β in µm per tooth and flank beside
geartopo's, the differences, the flagged rows and their likely cause).)");
}

} // namespace geartopo::python
