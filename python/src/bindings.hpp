// geartopo Python module — one function per part of the API, each in its own file, all called by module.cpp.
#pragma once

#include <pybind11/pybind11.h>

namespace geartopo::python {

void bind_errors(pybind11::module_& m);     ///< errors.cpp: InputError → geartopo.InputError (a ValueError)
void bind_scene(pybind11::module_& m);      ///< scene_binding.cpp: Scene, load_scene, scene_from_yaml
void bind_simulate(pybind11::module_& m);   ///< simulate_binding.cpp: simulate
void bind_evaluate(pybind11::module_& m);   ///< evaluate_binding.cpp: evaluate
void bind_machine_values(pybind11::module_& m); ///< machine_values_binding.cpp: machine_values
void bind_measured(pybind11::module_& m);   ///< measured_binding.cpp: compare, diagnose, plan
void bind_compensate(pybind11::module_& m); ///< compensate_binding.cpp: compensate
void bind_synth(pybind11::module_& m);      ///< synth_binding.cpp: synth
void bind_series(pybind11::module_& m);     ///< series_binding.cpp: series
void bind_custom_effect(pybind11::module_& m); ///< custom_effect_binding.cpp: custom_effect, Scene.with_effect

} // namespace geartopo::python
