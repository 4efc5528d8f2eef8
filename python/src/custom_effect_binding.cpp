// geartopo Python module — custom_effect(name, parameters, fn) and Scene.with_effect(effect): a law of the user's
// given as a Python function instead of a scene expression (docs/python.md, "Your own physics as a Python function").
// The function is called on batches — fn(params: dict of float, state: dict of 1-D numpy arrays, one per contact
// variable of effects::kContactVariableNames) -> 1-D array of the deviation in µm — with the GIL taken around the call
// only: the library's worker threads wait for it in turn (calls are serialised), and a batch is fixed by the work, not
// by the thread count, so the results are the same at any thread count. The scene then holds the law as an entry of
// custom_effects with `python: <module.qualname>` in place of `deviation_um`, read back by scene/custom_law_reader.cpp.
#include "bindings.hpp"
#include "interrupt.hpp"
#include "named_arguments.hpp"
#include "py_scene.hpp"

#include "geartopo/effects/custom_effect.hpp"
#include "geartopo/scene/scene.hpp"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <yaml-cpp/yaml.h>

#include <map>

namespace py = pybind11;

namespace geartopo::python {
namespace {

/// What geartopo.custom_effect returns: the registered law, and its values' standard uncertainties (the Monte Carlo
/// of compensate draws them, as an entry's `uncertainty`), by key.
struct PyCustomEffect {
  std::shared_ptr<const effects::CustomLaw> law;
  std::map<std::string, double> uncertainty;
};

double number_of(const py::dict& spec, const char* field, const std::string& key) {
  if (!spec.contains(field))
    throw py::value_error(fmt::format("parameter '{}': missing '{}' (each parameter needs value, min, max and unit)",
                                      key, field));
  return py::cast<double>(py::float_(spec[field]));
}

std::vector<effects::CustomParameter> parameters_of(const py::dict& parameters,
                                                    std::map<std::string, double>& uncertainty) {
  std::vector<effects::CustomParameter> out;
  for (const auto& [key, spec] : parameters) {
    effects::CustomParameter p;
    p.key = py::cast<std::string>(py::str(key));
    if (!py::isinstance<py::dict>(spec))
      throw py::type_error(fmt::format("parameters: '{}': expected a dict {{'value': …, 'min': …, 'max': …, 'unit': "
                                       "…}}",
                                       p.key));
    const auto s = py::reinterpret_borrow<py::dict>(spec);
    p.value = number_of(s, "value", p.key), p.min = number_of(s, "min", p.key), p.max = number_of(s, "max", p.key);
    if (!s.contains("unit") || py::cast<std::string>(py::str(s["unit"])).empty())
      throw py::value_error(fmt::format("parameters: '{}': say its unit (e.g. 'um_per_mm', 's')", p.key));
    p.unit = py::cast<std::string>(py::str(s["unit"]));
    if (s.contains("uncertainty")) uncertainty[p.key] = number_of(s, "uncertainty", p.key);
    for (const auto& [field, _] : s) {
      const auto f = py::cast<std::string>(py::str(field));
      if (f != "value" && f != "min" && f != "max" && f != "unit" && f != "uncertainty")
        throw py::value_error(
            fmt::format("parameters: '{}': unknown field '{}' (value, min, max, unit, uncertainty)", p.key, f));
    }
    out.push_back(std::move(p));
  }
  return out;
}

/// "module.qualname" of the function, what the scene and the report name the law by.
std::string qualified_name(const py::handle& fn) {
  const std::string module = py::cast<std::string>(py::str(py::getattr(fn, "__module__", py::str(""))));
  const py::object qual = py::getattr(fn, "__qualname__", py::none());
  const std::string name = qual.is_none() ? py::cast<std::string>(py::repr(fn)) : py::cast<std::string>(py::str(qual));
  return module.empty() || module == "None" ? name : module + "." + name;
}

std::string shape_of(const py::handle& r) {
  if (py::isinstance<py::array>(r)) {
    std::string s;
    const auto a = py::reinterpret_borrow<py::array>(r);
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s += fmt::format("{}{}", k ? ", " : "", a.shape(k));
    return fmt::format("an array of shape ({}{})", s, a.ndim() == 1 ? "," : "");
  }
  return fmt::format("a {}", py::cast<std::string>(py::str(py::type::of(r).attr("__name__"))));
}

/// The function as a batch law. `fn` is never released: the law may outlive the interpreter (the registry is static),
/// and a reference dropped then would touch a finished interpreter.
effects::BatchLaw batch_law(const py::function& fn, std::string name, std::string function_name,
                            std::shared_ptr<const effects::CustomLaw>* self) {
  auto* held = new py::object(fn); // NOLINT: kept for the process's life (see above)
  return [held, name = std::move(name), function_name = std::move(function_name),
          self](const std::vector<double>& values, std::span<const effects::ContactVariables> at,
                std::span<double> out) {
    const py::gil_scoped_acquire gil; // only around the call: the library's threads take turns here
    const auto n = static_cast<py::ssize_t>(at.size());
    py::dict params;
    const auto& declared = (*self)->declared();
    for (std::size_t k = 0; k < declared.size(); ++k) params[py::str(declared[k].key)] = values[k];
    py::dict state;
    for (std::size_t k = 0; k < effects::kContactVariableCount; ++k) {
      py::array_t<double> column(n);
      double* d = column.mutable_data();
      for (py::ssize_t i = 0; i < n; ++i) d[i] = effects::as_array(at[static_cast<std::size_t>(i)])[k];
      state[py::str(std::string(effects::kContactVariableNames[k]))] = std::move(column);
    }
    const py::object r = (*held)(params, state); // its exception goes to the caller as it is (error_already_set)
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(r);
    if (!a || a.ndim() != 1 || a.shape(0) != n)
      throw py::value_error(fmt::format(
          "custom effect '{}': the Python function {} returned {} for a batch of {} points; one value per point is "
          "expected, a 1-D array of shape ({},) (deviation µm, plus material). The batch's first point: {}",
          name, function_name, shape_of(r), n, n, effects::point_message(**self, at[0], values)));
    std::copy(a.data(), a.data() + n, out.begin());
  };
}

/// The functions made into laws in this process, by name: the same function under the same name again (a notebook's
/// cell run twice, other values) is the same law, so the registry takes it again.
struct Made {
  py::object* fn;
  std::shared_ptr<const effects::BatchLaw> function;
};
std::map<std::string, Made>& made() {
  static std::map<std::string, Made> m;
  return m;
}

PyCustomEffect custom_effect(const TextArg& name_arg, const py::object& parameters_arg, const py::object& fn_arg) {
  // Each argument converted here, so that a wrong one is refused naming it (named_arguments.hpp).
  const std::string name = text_argument(name_arg, "name");
  if (!py::isinstance<py::dict>(parameters_arg))
    throw py::type_error(fmt::format("parameters: {} is not a dict {{key: {{'value': …, 'min': …, 'max': …, 'unit': "
                                     "…}}}}",
                                     py::cast<std::string>(py::repr(parameters_arg))));
  if (!PyCallable_Check(fn_arg.ptr()))
    throw py::type_error(fmt::format("fn: {} is not callable (fn(params, state) -> numpy array)",
                                     py::cast<std::string>(py::repr(fn_arg))));
  const auto parameters = py::reinterpret_borrow<py::dict>(parameters_arg);
  const auto fn = py::reinterpret_borrow<py::function>(fn_arg);
  std::map<std::string, double> uncertainty;
  auto params = parameters_of(parameters, uncertainty);
  const std::string function_name = qualified_name(fn);
  std::shared_ptr<const effects::BatchLaw> function;
  std::shared_ptr<const effects::CustomLaw>* self = nullptr;
  if (const auto it = made().find(name); it != made().end() && it->second.fn->is(fn)) {
    function = it->second.function;
  } else {
    // The law refers to itself (its parameters' names, for the messages) through a slot filled once it exists.
    self = new std::shared_ptr<const effects::CustomLaw>(); // NOLINT: lives as long as the law (the process)
    function = std::make_shared<const effects::BatchLaw>(batch_law(fn, name, function_name, self));
  }
  auto law = std::make_shared<const effects::CustomLaw>(name, std::move(params), function, function_name);
  if (self) *self = law;
  effects::register_custom_law(law); // std::invalid_argument (a library name, another law) → ValueError
  if (self) made()[name] = Made{new py::object(fn), function}; // NOLINT: kept for the process's life
  return PyCustomEffect{law, std::move(uncertainty)};
}

/// The scene's YAML with the effect's entry added to custom_effects (made when missing).
std::string yaml_with(const std::string& text, const PyCustomEffect& effect) {
  const effects::CustomLaw& law = *effect.law;
  YAML::Node root = YAML::Load(text);
  YAML::Node entry;
  entry["name"] = law.name();
  YAML::Node params(YAML::NodeType::Map);
  for (const auto& p : law.declared()) {
    YAML::Node q;
    q.SetStyle(YAML::EmitterStyle::Flow);
    // The shortest text that reads back as the same double (0.04, not 0.040000000000000001).
    q["value"] = fmt::format("{}", p.value), q["min"] = fmt::format("{}", p.min), q["max"] = fmt::format("{}", p.max);
    q["unit"] = p.unit;
    params[p.key] = q;
  }
  entry["parameters"] = params;
  if (!effect.uncertainty.empty()) {
    YAML::Node u(YAML::NodeType::Map);
    u.SetStyle(YAML::EmitterStyle::Flow);
    for (const auto& [key, sigma] : effect.uncertainty) u[key] = fmt::format("{}", sigma);
    entry["uncertainty"] = u;
  }
  entry["python"] = law.expression();
  if (law.dressing_interval_strokes() > 0) entry["dressing_interval_strokes"] = law.dressing_interval_strokes();
  root["custom_effects"].push_back(entry);
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

PyScene with_effect(const PyScene& s, const py::object& effect) {
  if (!py::isinstance<PyCustomEffect>(effect))
    throw py::type_error(fmt::format("effect: {} is not a geartopo.CustomEffect (made by geartopo.custom_effect)",
                                     py::cast<std::string>(py::repr(effect))));
  const auto& e = effect.cast<const PyCustomEffect&>();
  PyScene out;
  out.text = yaml_with(s.text, e);
  out.source = s.source;
  out.dir = s.dir;
  const LibraryWork work; // Ctrl-C caught, the GIL released (the scene's checks call the function: it takes it)
  out.wb = std::make_shared<const workbench::Workbench>(scene::parse_scene(out.text, s.source), interrupt_check());
  return out;
}

} // namespace

void bind_custom_effect(py::module_& m) {
  py::class_<PyCustomEffect>(m, "CustomEffect",
                             "A law of yours given as a Python function (geartopo.custom_effect): add it to a scene "
                             "with Scene.with_effect(effect).")
      .def_property_readonly("name", [](const PyCustomEffect& e) { return e.law->name(); })
      .def_property_readonly("function_name", [](const PyCustomEffect& e) { return e.law->expression(); })
      .def_property_readonly("explanation", [](const PyCustomEffect& e) { return e.law->explanation(); })
      .def_property_readonly("parameters", [](const PyCustomEffect& e) {
        py::dict d;
        for (const auto& p : e.law->declared()) {
          py::dict q(py::arg("value") = p.value, py::arg("min") = p.min, py::arg("max") = p.max, py::arg("unit") = p.unit);
          if (const auto u = e.uncertainty.find(p.key); u != e.uncertainty.end()) q["uncertainty"] = u->second;
          d[py::str(p.key)] = q;
        }
        return d;
      })
      .def("__repr__", [](const PyCustomEffect& e) {
        return fmt::format("<geartopo.CustomEffect '{}': {}>", e.law->name(), e.law->expression());
      });
  m.def("custom_effect", &custom_effect, py::arg("name"), py::arg("parameters"), py::arg("fn"),
        "Your own physics as a Python function: fn(params, state) -> deviation (µm, plus material) per point, where "
        "params maps each parameter to its value (float) and state each contact variable (t_s, stroke, "
        "strokes_since_dressing, tooth, side, x_mm, y_mm, z_mm, r_mm, roll_mm, nx, ny, nz, c_deg, X_mm, Y_mm, Z_mm, "
        "A_deg, wheel_r_mm; docs/scene-format.md) to a 1-D numpy array over a batch of points. parameters: "
        "{key: {'value': …, 'min': …, 'max': …, 'unit': …, 'uncertainty': σ (optional: the Monte Carlo draws it)}}. "
        "Registered under `name` for this process (a name is "
        "given to one law only). docs/python.md.");
  py::object scene = m.attr("Scene");
  scene.attr("with_effect") = py::cpp_function(
      &with_effect, py::name("with_effect"), py::is_method(scene), py::arg("effect"),
      "This scene with your effect (geartopo.custom_effect) added to custom_effects: simulate and synth use it at its "
      "values, diagnose fits it, compensate compensates it. The YAML is written again (comments dropped).");
}

} // namespace geartopo::python
