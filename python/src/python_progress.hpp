// geartopo Python module — a Python progress callback as the libraries' progress function. The long calls run with
// the GIL released (py::gil_scoped_release) and the libraries report from their worker threads: each report takes
// the GIL, calls progress(done, total) and lets it go. An exception the callback raises (KeyboardInterrupt, a
// script's own stop) stops the work as any exception of a progress function does, and reaches the caller. Every
// report also checks for Ctrl-C (interrupt.hpp), with or without a callback.
#pragma once

#include "interrupt.hpp"

#include <pybind11/pybind11.h>

#include <fmt/format.h>

#include <functional>
#include <mutex>

namespace geartopo::python {

/// `callback` (None or a callable(done, total)) must outlive the returned function, which holds a reference to it:
/// a py::object may be copied or destroyed only with the GIL held, and the function is copied and destroyed in the
/// libraries without it. For None, the function only checks for Ctrl-C. One report at a time, in the order the
/// workers make them. A `callback` that cannot be called is a TypeError naming `progress`.
inline std::function<void(long long, long long)> progress_function(const pybind11::object& callback) {
  if (callback.is_none()) return [](long long, long long) { throw_if_interrupted(); };
  if (!PyCallable_Check(callback.ptr()))
    throw pybind11::type_error(fmt::format("progress: {} is not callable (None or a callable(done, total))",
                                           pybind11::repr(callback).cast<std::string>()));
  const pybind11::object* f = &callback;
  auto serial = std::make_shared<std::mutex>();
  return [f, serial](long long done, long long total) {
    throw_if_interrupted();
    const std::lock_guard lock(*serial);
    const pybind11::gil_scoped_acquire gil;
    (*f)(done, total);
  };
}

} // namespace geartopo::python
