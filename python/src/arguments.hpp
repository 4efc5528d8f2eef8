// geartopo Python module — the arguments several functions take, checked as the CLI checks its flags (a wrong word
// or number is a ValueError naming the argument).
#pragma once

#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"

#include <pybind11/pybind11.h>

#include <string>
#include <utility>
#include <vector>

namespace geartopo::python {

/// teeth=None → `fallback`; "all" → {} (every tooth); a sequence of tooth numbers 1..z, none twice.
std::vector<int> teeth_argument(const pybind11::object& teeth, int z, const std::vector<int>& fallback);
/// A file's path: a str or an os.PathLike naming one (TypeError otherwise, naming `argument`); empty or holding a
/// NUL character: ValueError (commands::check_path) — a C string would end at the NUL and name another file.
std::string path_argument(const pybind11::object& path, const char* argument);
/// A grid's (rows, cols): a pair of whole numbers, each 2 … 1000 (commands::kMaxGridLines); otherwise a TypeError or
/// ValueError naming `argument`.
std::pair<int, int> grid_argument(const pybind11::object& grid, const char* argument);
/// "exact" or "linear".
grinding::Method method_argument(const std::string& method);
/// iso_direction "transverse"|"normal", helix_slope_sign "helix-angle"|"rise-towards-plus-z".
workbench::IsoOptions iso_arguments(const std::string& iso_direction, const std::string& helix_slope_sign);

} // namespace geartopo::python
