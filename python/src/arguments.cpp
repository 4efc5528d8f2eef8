#include "arguments.hpp"

#include "geartopo/commands/limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace py = pybind11;

namespace geartopo::python {

std::string path_argument(const py::object& path, const char* argument) {
  py::object text = path;
  if (!py::isinstance<py::str>(path)) {
    if (!py::hasattr(path, "__fspath__"))
      throw py::type_error(fmt::format("{}: {} is not a path (a str or an os.PathLike)", argument,
                                       py::repr(path).cast<std::string>()));
    text = path.attr("__fspath__")();
    if (!py::isinstance<py::str>(text))
      throw py::type_error(fmt::format("{}: {} is not a path given as text (bytes paths are not read)", argument,
                                       py::repr(path).cast<std::string>()));
  }
  std::string s = text.cast<std::string>();
  commands::check_path(s, argument);
  return s;
}

std::pair<int, int> grid_argument(const py::object& grid, const char* argument) {
  const auto shown = [&] { return py::repr(grid).cast<std::string>(); };
  if (!(py::isinstance<py::tuple>(grid) || py::isinstance<py::list>(grid)) || py::len(grid) != 2)
    throw py::type_error(fmt::format("{}: {} is not (rows, cols), e.g. (40, 60)", argument, shown()));
  int rc[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const py::object v = grid[py::int_(k)];
    if (py::isinstance<py::bool_>(v) || (!py::isinstance<py::int_>(v) && !py::hasattr(v, "__index__")))
      throw py::type_error(fmt::format("{}: {} is not (rows, cols) of whole numbers", argument, shown()));
    const auto n = py::int_(v.attr("__index__")()).cast<long long>();
    if (n < 2 || n > commands::kMaxGridLines)
      throw std::invalid_argument(
          fmt::format("{}: {} is not (rows, cols) with 2 ≤ each ≤ {}", argument, shown(), commands::kMaxGridLines));
    rc[k] = static_cast<int>(n);
  }
  return {rc[0], rc[1]};
}

std::vector<int> teeth_argument(const py::object& teeth, int z, const std::vector<int>& fallback) {
  if (teeth.is_none()) return fallback;
  if (py::isinstance<py::str>(teeth)) {
    if (teeth.cast<std::string>() == "all") return {};
    throw std::invalid_argument(fmt::format("teeth: '{}' is not \"all\" or a list of tooth numbers (e.g. [1, 18])",
                                            teeth.cast<std::string>()));
  }
  // A mapping or a set is not a list of teeth ({1: 18} iterated as [1]); a single number is not a list either.
  if (py::isinstance<py::dict>(teeth) || py::isinstance<py::set>(teeth) || py::isinstance<py::frozenset>(teeth) ||
      !py::hasattr(teeth, "__iter__"))
    throw py::type_error(fmt::format("teeth: {} is not \"all\" or a list of tooth numbers (e.g. [1, 18])",
                                     py::repr(teeth).cast<std::string>()));
  std::vector<int> out;
  for (const auto& item : py::iter(teeth)) {
    // A tooth is a whole number: 1.5 or True is refused, not truncated to 1 (an integral float such as 18.0 is read).
    const auto object = py::reinterpret_borrow<py::object>(item);
    if (py::isinstance<py::bool_>(object) ||
        (py::isinstance<py::float_>(object) && object.cast<double>() != std::floor(object.cast<double>())) ||
        !(py::isinstance<py::int_>(object) || py::isinstance<py::float_>(object) || py::hasattr(object, "__index__")))
      throw std::invalid_argument(fmt::format("teeth: {} is not a tooth number (a whole number of 1..{})",
                                              py::repr(object).cast<std::string>(), z));
    const double as_double = py::float_(object).cast<double>();
    if (!std::isfinite(as_double) || std::abs(as_double) > 1e9)
      throw std::invalid_argument(fmt::format("teeth: {} is not a tooth number of 1..{}", py::repr(object).cast<std::string>(), z));
    const long long v = py::int_(object).cast<long long>();
    if (v < 1 || v > z) throw std::invalid_argument(fmt::format("teeth: {} is not a tooth number of 1..{}", v, z));
    if (std::find(out.begin(), out.end(), static_cast<int>(v)) != out.end())
      throw std::invalid_argument(fmt::format("teeth: tooth {} is listed twice", v));
    out.push_back(static_cast<int>(v));
  }
  if (out.empty()) throw std::invalid_argument("teeth: an empty list (use e.g. [1, 18] or \"all\")");
  return out;
}

grinding::Method method_argument(const std::string& method) {
  if (method == "exact") return grinding::Method::Exact;
  if (method == "linear") return grinding::Method::Linear;
  throw std::invalid_argument(fmt::format("method: '{}' is not exact or linear", method));
}

workbench::IsoOptions iso_arguments(const std::string& iso_direction, const std::string& helix_slope_sign) {
  workbench::IsoOptions o;
  const auto d = evaluation::parse_iso_direction(iso_direction);
  if (!d) throw std::invalid_argument(fmt::format("iso_direction: '{}' is not transverse or normal", iso_direction));
  const auto s = evaluation::parse_helix_slope_sign(helix_slope_sign);
  if (!s)
    throw std::invalid_argument(
        fmt::format("helix_slope_sign: '{}' is not helix-angle or rise-towards-plus-z", helix_slope_sign));
  o.direction = *d;
  o.helix_slope_sign = *s;
  return o;
}

} // namespace geartopo::python
