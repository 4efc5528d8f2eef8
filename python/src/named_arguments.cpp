// geartopo Python module — arguments converted where their name is known (named_arguments.hpp).
#include "named_arguments.hpp"

#include <fmt/format.h>

#include <limits>
#include <stdexcept>

namespace py = pybind11;

namespace geartopo::python {
namespace {

std::string shown(const py::object& v) {
  std::string s = py::repr(v).cast<std::string>();
  if (s.size() > 80) s = s.substr(0, 77) + "...";
  return s;
}

bool is_flag(const py::object& v) {
  if (py::isinstance<py::bool_>(v)) return true;
  const py::object type = py::type::of(v);
  return py::hasattr(type, "__module__") && py::str(type.attr("__module__")).cast<std::string>() == "numpy" &&
         py::str(type.attr("__name__")).cast<std::string>() == "bool_";
}

/// numbers.Real / numbers.Integral: int, float, Fraction, numpy's numbers — not complex, str, Decimal or None.
bool is_instance_of_abc(const py::object& v, const char* abc) {
  return py::isinstance(v, py::module_::import("numbers").attr(abc));
}

} // namespace

double real_argument(const RealArg& a, const char* name) {
  const py::object& v = a.value;
  if (is_flag(v) || !is_instance_of_abc(v, "Real"))
    throw py::type_error(fmt::format("{}: {} is not a number (an int or a float)", name, shown(v)));
  try {
    return py::float_(v).cast<double>();
  } catch (const py::error_already_set&) { // an int beyond a double's range
    throw std::invalid_argument(fmt::format("{}: {} is not a number a double holds", name, shown(v)));
  }
}

long long whole_argument(const WholeArg& a, const char* name, long long lo, long long hi) {
  const py::object& v = a.value;
  if (is_flag(v) || !is_instance_of_abc(v, "Integral"))
    throw py::type_error(fmt::format("{}: {} is not a whole number (an int)", name, shown(v)));
  const py::int_ n(v.attr("__index__")());
  // Compared as Python ints: 10**30 is refused with the range, not by an overflow of the conversion.
  if (n < py::int_(lo) || n > py::int_(hi))
    throw std::invalid_argument(fmt::format("{}: {} is not a whole number of {} … {}", name, shown(v), lo, hi));
  return n.cast<long long>();
}

std::uint64_t seed_argument(const WholeArg& a, const char* name) {
  const py::object& v = a.value;
  if (is_flag(v) || !is_instance_of_abc(v, "Integral"))
    throw py::type_error(fmt::format("{}: {} is not a whole number (an int)", name, shown(v)));
  const py::int_ n(v.attr("__index__")());
  const py::int_ most(std::numeric_limits<std::uint64_t>::max());
  if (n < py::int_(0) || n > most)
    throw std::invalid_argument(fmt::format("{}: {} is not a seed: 0 … 2**64 − 1", name, shown(v)));
  return n.cast<std::uint64_t>();
}

std::string text_argument(const TextArg& a, const char* name) {
  if (!py::isinstance<py::str>(a.value))
    throw py::type_error(fmt::format("{}: {} is not a str", name, shown(a.value)));
  return a.value.cast<std::string>();
}

bool flag_argument(const FlagArg& a, const char* name) {
  if (!is_flag(a.value)) throw py::type_error(fmt::format("{}: {} is not True or False", name, shown(a.value)));
  return py::bool_(a.value).cast<bool>();
}

std::vector<std::string> text_list_argument(const TextListArg& a, const char* name) {
  const py::object& v = a.value;
  if (!(py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)))
    throw py::type_error(fmt::format("{}: {} is not a list of str", name, shown(v)));
  std::vector<std::string> out;
  for (const auto& item : v) {
    if (!py::isinstance<py::str>(item))
      throw py::type_error(fmt::format("{}: {} in {} is not a str", name, shown(py::reinterpret_borrow<py::object>(item)),
                                       shown(v)));
    out.push_back(item.cast<std::string>());
  }
  return out;
}

const PyScene& scene_argument(const SceneArg& a, const char* name) {
  if (!py::isinstance<PyScene>(a.value))
    throw py::type_error(fmt::format("{}: {} is not a geartopo.Scene (geartopo.load_scene(path) or "
                                     "geartopo.scene_from_yaml(text) makes one)",
                                     name, shown(a.value)));
  return a.value.cast<const PyScene&>();
}

} // namespace geartopo::python
