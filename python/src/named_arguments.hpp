// geartopo Python module — arguments converted where their name is known. pybind11 converts a typed argument
// (double, std::string, bool, …) before the function runs, and one that does not convert is refused with a bare
// "incompatible function arguments" naming none of them. An argument of the types below is taken as Python gives it
// (their casters accept any object; the signature still shows float, int, str, bool, List[str], geartopo.Scene) and
// converted in the function's body by the function of its type, which names it: `noise_um: 'x' is not a number`.
#pragma once

#include "py_scene.hpp"

#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

namespace geartopo::python {

/// threads: 0 (all hardware threads) … this; more than the work has are not started (core/parallel.hpp).
inline constexpr long long kMaxThreads = 1024;

struct RealArg { pybind11::object value; };     ///< shown as float
struct WholeArg { pybind11::object value; };    ///< shown as int
struct TextArg { pybind11::object value; };     ///< shown as str
struct FlagArg { pybind11::object value; };     ///< shown as bool
struct TextListArg { pybind11::object value; }; ///< shown as List[str]
struct SceneArg { pybind11::object value; };    ///< shown as geartopo.Scene

/// A real number (int, float, numpy's): TypeError naming `name` for anything else (bool, str, complex, None, …).
/// Not checked for finiteness or range: the callers' bounds do that and say what is expected.
double real_argument(const RealArg& a, const char* name);
/// A whole number (int, numpy's integers; not bool, not float) within [lo, hi]: TypeError or ValueError naming `name`.
long long whole_argument(const WholeArg& a, const char* name, long long lo, long long hi);
/// A seed: a whole number 0 … 2⁶⁴ − 1.
std::uint64_t seed_argument(const WholeArg& a, const char* name);
/// A str (bytes and anything else: TypeError naming `name`).
std::string text_argument(const TextArg& a, const char* name);
/// True or False (numpy's too); 1, "yes", None: TypeError naming `name`.
bool flag_argument(const FlagArg& a, const char* name);
/// A list or tuple of str (a str itself is not a list of words).
std::vector<std::string> text_list_argument(const TextListArg& a, const char* name);
/// A geartopo.Scene (made by load_scene or scene_from_yaml); alive while `a` is.
const PyScene& scene_argument(const SceneArg& a, const char* name);

} // namespace geartopo::python

namespace pybind11::detail {

// Each takes any object (converted by the function of its type, above); the signature shows the type it stands for.
#define GEARTOPO_ANY_OBJECT_CASTER(Type, shown)                                                                      \
  template <>                                                                                                        \
  struct type_caster<Type> {                                                                                         \
    PYBIND11_TYPE_CASTER(Type, const_name(shown));                                                                   \
    bool load(handle src, bool) {                                                                                    \
      value.value = reinterpret_borrow<object>(src);                                                                 \
      return true;                                                                                                   \
    }                                                                                                                \
    static handle cast(const Type& v, return_value_policy, handle) { return v.value.inc_ref(); }                    \
  }

GEARTOPO_ANY_OBJECT_CASTER(geartopo::python::RealArg, "float");
GEARTOPO_ANY_OBJECT_CASTER(geartopo::python::WholeArg, "int");
GEARTOPO_ANY_OBJECT_CASTER(geartopo::python::TextArg, "str");
GEARTOPO_ANY_OBJECT_CASTER(geartopo::python::FlagArg, "bool");
GEARTOPO_ANY_OBJECT_CASTER(geartopo::python::TextListArg, "List[str]");
GEARTOPO_ANY_OBJECT_CASTER(geartopo::python::SceneArg, "geartopo.Scene");

#undef GEARTOPO_ANY_OBJECT_CASTER

} // namespace pybind11::detail
