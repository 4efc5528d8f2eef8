// geartopo Python module — a Python progress callback as the libraries' progress function. The long calls run with
// the GIL released (py::gil_scoped_release) and the libraries report from their worker threads: each report takes
// the GIL, calls progress(done, total) and lets it go. An exception the callback raises (KeyboardInterrupt, a
// script's own stop) stops the work as any exception of a progress function does, and reaches the caller.
#pragma once

#include <pybind11/pybind11.h>

#include <functional>
#include <mutex>

namespace geartopo::python {

/// `callback` (None or a callable(done, total)) must outlive the returned function, which holds a reference to it:
/// a py::object may be copied or destroyed only with the GIL held, and the function is copied and destroyed in the
/// libraries without it. Empty for None. One report at a time, in the order the workers make them.
inline std::function<void(long long, long long)> progress_function(const pybind11::object& callback) {
  if (callback.is_none()) return {};
  const pybind11::object* f = &callback;
  auto serial = std::make_shared<std::mutex>();
  return [f, serial](long long done, long long total) {
    const std::lock_guard lock(*serial);
    const pybind11::gil_scoped_acquire gil;
    (*f)(done, total);
  };
}

} // namespace geartopo::python
