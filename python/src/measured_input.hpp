// geartopo Python module — a measurement as Python gives it: the path of a measurement file (every format the CLI's
// --measured reads, told apart by content: measurement::read_any_measurement) or a dict of arrays with topology.csv's
// columns (synth()'s result, or a user's own: tooth, flank, diameter_mm, z_mm, deviation_um; row, col and design_um
// optional), checked as the topology reader checks a file, each fault located at its 1-based element.
#pragma once

#include "py_scene.hpp"

#include "geartopo/measurement/measured_points.hpp"

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace geartopo::python {

/// What `against` (the keyword measured_against) says a measurement without a design_um column is measured from:
/// None — as the file says (the scene's measurement.measured_against for the scene's own file), "design" or
/// "involute"; anything else: TypeError / ValueError naming the keyword.
measurement::MeasuredAgainst measured_against_argument(const pybind11::object& against);

/// The measured points on the scene's gear, referred to the scene's design as the CLI refers a file's; `name` gets
/// the file's path or "measured arrays" (what the JSON results name as "measured"). `against`: what a file or arrays
/// without design_um are measured from (measured_against_argument; as_file and the scene's own file: the scene's
/// measurement.measured_against). Reader warnings become Python warnings.
std::vector<measurement::MeasuredPoint> measured_points(const PyScene& scene, const pybind11::object& measured,
                                                        std::string& name,
                                                        measurement::MeasuredAgainst against =
                                                            measurement::MeasuredAgainst::as_file);

} // namespace geartopo::python
