// geartopo Python module — machine_values(scene, export, values): the measuring machine's own evaluation beside
// geartopo's evaluation of the same traces (workbench::compare_machine_pitch, compare_machine_flank_values), as
// `geartopo evaluate --traces EXPORT.mka [--machine-values EXPORT.mew]` writes it into iso1328.json
// (report::machine_pitch_table_json, machine_flank_values_json).
#include "arguments.hpp"
#include "bindings.hpp"
#include "json_to_python.hpp"
#include "py_scene.hpp"

#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/measurement/klingelnberg_values.hpp"
#include "geartopo/report/machine_values_report.hpp"

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
      [](const PyScene& s, const py::object& export_path, const py::object& values_path, const std::string& iso_direction,
         const std::string& helix_slope_sign) {
        const auto& wb = *s.wb;
        const workbench::IsoOptions iso = iso_arguments(iso_direction, helix_slope_sign);
        const std::string file = py::str(export_path).cast<std::string>();
        const std::string values_file = values_path.is_none() ? std::string() : py::str(values_path).cast<std::string>();
        {
          std::ifstream in(file, std::ios::binary); // unreadable: the reader below says why
          if (in && !measurement::looks_like_klingelnberg(in))
            throw std::invalid_argument(file + " is not a Klingelnberg export: the machine's values are compared with "
                                               "geartopo's evaluation of an export's curves (.mka)");
        }
        std::vector<std::string> warnings;
        std::vector<grinding::FlankTopology> flanks;
        std::optional<measurement::KlingelnbergFile> curves;
        std::optional<measurement::KlingelnbergValues> machine;
        workbench::IsoResult result;
        std::optional<workbench::MachinePitchComparison> pitch;
        std::optional<workbench::MachineFlankComparison> flank_values;
        {
          const py::gil_scoped_release nogil;
          auto traces = measurement::read_any_traces(file, wb.setup);
          warnings = std::move(traces.warnings);
          flanks = std::move(traces.flanks);
          curves = std::move(traces.export_file);
          if (!values_file.empty()) {
            machine = measurement::read_klingelnberg_values(values_file);
            if (!machine->unknown_lines.empty())
              warnings.push_back(fmt::format("{}: result lines not read (sizes and other codes): {}", values_file,
                                             fmt::join(machine->unknown_lines, ", ")));
          } else {
            // As the CLI: a value file beside the export is not read unless named (a stale one would be compared).
            if (const auto beside_mew = measurement::value_file_beside(file))
              warnings.push_back(fmt::format("{} beside the export is not read: give values=\"{}\" to compare the "
                                             "machine's profile and helix values",
                                             *beside_mew, *beside_mew));
          }
          result = workbench::evaluate_iso(wb.setup.geometry(), wb.setup.ranges(), flanks, iso);
          if (curves && !curves->pitch.empty()) pitch = workbench::compare_machine_pitch(curves->pitch, result.evaluation);
          if (machine)
            flank_values = workbench::compare_machine_flank_values(*machine, wb.setup.geometry(), wb.setup.ranges(),
                                                                   flanks, result.evaluation, curves ? &*curves : nullptr);
        }
        if (!warnings.empty()) {
          const auto warn = py::module_::import("warnings").attr("warn");
          for (const auto& w : warnings) warn(w);
        }
        nlohmann::json j = nlohmann::json::object();
        if (pitch) j["machine_pitch_table"] = report::machine_pitch_table_json(*pitch);
        if (flank_values) j["machine_flank_values"] = report::machine_flank_values_json(*flank_values, *machine);
        return to_python(j);
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
