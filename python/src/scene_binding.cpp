// geartopo Python module — Scene, load_scene(path), scene_from_yaml(text): the scene read and built by the same
// functions as every CLI command (scene::load_scene / parse_scene, workbench::Workbench).
#include "bindings.hpp"
#include "arguments.hpp"
#include "interrupt.hpp"
#include "named_arguments.hpp"
#include "json_to_python.hpp"
#include "py_scene.hpp"

#include "geartopo/files/input_file.hpp"
#include "geartopo/report/gear_report.hpp"
#include "geartopo/scene/scene.hpp"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

namespace py = pybind11;

namespace geartopo::python {
namespace {

PyScene make_scene(scene::Scene s, std::string source, std::string text) {
  PyScene out;
  out.dir = std::filesystem::path(source).parent_path();
  out.source = std::move(source);
  out.text = std::move(text);
  // Checked for Ctrl-C between its steps and before every grid row of the custom effects' check
  out.wb = std::make_shared<const workbench::Workbench>(std::move(s), interrupt_check());
  return out;
}

} // namespace

void bind_scene(py::module_& m) {
  py::class_<PyScene>(m, "Scene", "A scene: gear, wheel, machine, process, grid and effects, built and checked once "
                                  "(docs/scene-format.md). Made by load_scene or scene_from_yaml.")
      .def_property_readonly("name", [](const PyScene& s) { return s.wb->scene.name; })
      .def_property_readonly("source", [](const PyScene& s) { return s.source; },
                             "The scene file, or the name given to scene_from_yaml")
      .def_property_readonly("yaml", [](const PyScene& s) { return s.text; }, "The scene's YAML text")
      .def_property_readonly("teeth", [](const PyScene& s) { return s.wb->setup.geometry().teeth(); })
      .def_property_readonly("measured", [](const PyScene& s) -> py::object {
            if (s.wb->scene.grid.measured_file.empty()) return py::none();
            return py::str(s.wb->scene.grid.measured_file);
          }, "The scene's demo measurement (measurement.measured) as a path usable from the working folder — resolved "
             "against the scene file's folder — or None")
      .def_property_readonly(
          "gear",
          [](const PyScene& s) {
            // Read-only: a scene is built and checked once, so an assignment to a copy would be silently lost.
            const py::object types = py::module_::import("types");
            return types.attr("MappingProxyType")(to_python(report::gear_json(s.wb->scene, s.wb->setup.geometry())));
          },
          "The gear's geometry (ISO 21771) as `geartopo gear --json` prints it: a read-only mapping, units in the keys. "
          "To change a scene, edit its YAML text (Scene.yaml) and read it again with scene_from_yaml(text, "
          "source=scene.source) (docs/python.md, \"Changing a scene\")")
      .def_property_readonly("notes", [](const PyScene& s) { return s.wb->notes; },
                             "What was chosen for the user (e.g. a wheel diameter), as the CLI prints as notes")
      .def("__repr__", [](const PyScene& s) { return "<geartopo.Scene '" + s.wb->scene.name + "' from " + s.source + ">"; })
      // Scene.__new__(Scene) made an object with no scene inside, on which every property read freed memory: a Scene
      // is only made by load_scene and scene_from_yaml (the module makes its objects without __new__).
      .def_static("__new__", [](const py::args&, const py::kwargs&) -> py::object {
        throw py::type_error("geartopo.Scene cannot be made directly: use geartopo.load_scene(path) or "
                             "geartopo.scene_from_yaml(text, source=...)");
      });

  m.def(
      "load_scene",
      [](const py::object& path) {
        const std::filesystem::path file = path_argument(path, "path");
        std::string text = input::read_input_file(file, input::kMaxSceneBytes, "scene");
        const LibraryWork work; // Ctrl-C caught, the GIL released: the form wheel's synthesis takes a while
        return make_scene(scene::load_scene(file), file.string(), std::move(text));
      },
      py::arg("path"),
      "Reads a scene file (YAML). Raises geartopo.InputError (a ValueError) located at file:line:column and field.");
  m.def(
      "scene_from_yaml",
      [](const TextArg& text_arg, const TextArg& source_arg) {
        const std::string text = text_argument(text_arg, "text");
        const std::string source = text_argument(source_arg, "source");
        const LibraryWork work; // Ctrl-C caught, the GIL released
        return make_scene(scene::parse_scene(text, source), source, text);
      },
      py::arg("text"), py::arg("source") = "<yaml>",
      "A scene from YAML text. `source` names it in error messages; its folder is where relative paths "
      "(machine.tables, measurement.measured) start (default '<yaml>': the current folder).");
}

} // namespace geartopo::python
