// geartopo Python module — a JSON document as Python objects (dict, list, str, int, float, bool, None): the values
// of the CLI's JSON files (iso1328.json, compare.json, diagnosis.json, plan.json, prediction.json), built by the same
// report functions, so a script reads the same keys and values as the files hold.
#pragma once

#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>

namespace geartopo::python {

pybind11::object to_python(const nlohmann::json& j);

} // namespace geartopo::python
