// geartopo Python module: the main job with numpy arrays in and out (docs/python.md). The work is the libraries'
// (the same calls the CLI's commands make); this module converts arguments and results and nothing else.
#include "bindings.hpp"

PYBIND11_MODULE(geartopo, m) {
  m.doc() = "geartopo — tooth-flank topology of profile-ground helical gears (units in every key: mm, µm, deg). "
            "See docs/python.md.";
  m.attr("__version__") = GEARTOPO_VERSION;
  geartopo::python::bind_errors(m);
  geartopo::python::bind_scene(m);
  geartopo::python::bind_simulate(m);
  geartopo::python::bind_evaluate(m);
  geartopo::python::bind_machine_values(m);
  geartopo::python::bind_measured(m);
  geartopo::python::bind_compensate(m);
  geartopo::python::bind_synth(m);
  geartopo::python::bind_series(m);
  geartopo::python::bind_custom_effect(m);
}
