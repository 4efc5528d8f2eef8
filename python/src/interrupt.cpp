// geartopo Python module — Ctrl-C during a long call (interrupt.hpp).
#include "interrupt.hpp"

#include <atomic>
#include <csignal>
#include <mutex>

namespace geartopo::python {

namespace {

std::atomic<bool> g_interrupted{false}; // set by the handler: lock-free, async-signal-safe
std::atomic<bool> g_seen{false};        // the work stopped on it (the caller gets KeyboardInterrupt from the throw)
std::mutex g_scope_mutex;               // guards the two below
int g_depth = 0;
struct sigaction g_python_handler {};

extern "C" void on_sigint(int) { g_interrupted.store(true); }

} // namespace

InterruptScope::InterruptScope() {
  const std::lock_guard lock(g_scope_mutex);
  if (g_depth++ > 0) return;
  g_interrupted.store(false);
  g_seen.store(false);
  struct sigaction ours {};
  ours.sa_handler = on_sigint;
  sigemptyset(&ours.sa_mask);
  ours.sa_flags = SA_RESTART;
  sigaction(SIGINT, &ours, &g_python_handler);
}

InterruptScope::~InterruptScope() {
  const std::lock_guard lock(g_scope_mutex);
  if (--g_depth > 0) return;
  sigaction(SIGINT, &g_python_handler, nullptr);
  // A Ctrl-C no progress report saw (work without reports, or pressed after the last): Python's, as if just pressed.
  if (g_interrupted.load() && !g_seen.load()) {
    const pybind11::gil_scoped_acquire gil;
    PyErr_SetInterrupt();
  }
}

void throw_if_interrupted() {
  if (g_interrupted.load()) {
    g_seen.store(true);
    throw Interrupted{};
  }
}

} // namespace geartopo::python
