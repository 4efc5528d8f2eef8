// geartopo Python module — errors. A located input error (geartopo::InputError, "file:line:column: field: message",
// what the CLI prints before exiting with 1) becomes geartopo.InputError, a ValueError with the same message and its
// parts as attributes (file, line, column, field, message). pybind11 itself turns std::invalid_argument and
// std::domain_error into ValueError and other std::exception into RuntimeError; Ctrl-C during a call (interrupt.hpp)
// becomes KeyboardInterrupt.
#include "bindings.hpp"

#include "interrupt.hpp"

#include "geartopo/core/input_error.hpp"

#include <pybind11/eval.h>

namespace py = pybind11;

namespace geartopo::python {

void bind_errors(py::module_& m) {
  // A heap object that lives as long as the interpreter: the translator below refers to it.
  static py::handle input_error = [&] {
    py::exec(R"(
class InputError(ValueError):
    """Bad input, located: str(e) is "file:line:column: field: message" (parts unknown are left out); the parts are
    e.file, e.line and e.column (0 when unknown), e.field and e.message."""
)",
             m.attr("__dict__"));
    py::object cls = m.attr("InputError");
    return cls.release(); // kept for the interpreter's life
  }();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      py::object err = input_error(e.what());
      err.attr("file") = e.file();
      err.attr("line") = e.line();
      err.attr("column") = e.column();
      err.attr("field") = e.field();
      err.attr("message") = e.message();
      PyErr_SetObject(input_error.ptr(), err.ptr());
    } catch (const Interrupted&) {
      PyErr_SetNone(PyExc_KeyboardInterrupt);
    }
  });
}

} // namespace geartopo::python
