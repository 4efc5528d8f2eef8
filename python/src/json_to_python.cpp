#include "json_to_python.hpp"

namespace py = pybind11;

namespace geartopo::python {

py::object to_python(const nlohmann::json& j) {
  switch (j.type()) {
  case nlohmann::json::value_t::null:
  case nlohmann::json::value_t::discarded: return py::none();
  case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
  case nlohmann::json::value_t::number_integer: return py::int_(j.get<long long>());
  case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<unsigned long long>());
  case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
  case nlohmann::json::value_t::string: return py::str(j.get_ref<const std::string&>());
  case nlohmann::json::value_t::binary: return py::bytes(std::string(j.get_binary().begin(), j.get_binary().end()));
  case nlohmann::json::value_t::array: {
    py::list out;
    for (const auto& item : j) out.append(to_python(item));
    return out;
  }
  case nlohmann::json::value_t::object: {
    py::dict out;
    for (const auto& [key, value] : j.items()) out[py::str(key)] = to_python(value);
    return out;
  }
  }
  return py::none();
}

} // namespace geartopo::python
