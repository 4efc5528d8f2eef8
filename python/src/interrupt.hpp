// geartopo Python module — Ctrl-C during a long call. The libraries work with the GIL released, on worker threads,
// where Python's own check (PyErr_CheckSignals) does nothing and its SIGINT handler only marks a flag the interpreter
// reads once the call returns: a `compensate(samples=10**5)` ran on to its end. So, for the call's duration, SIGINT
// sets a flag of ours instead, which every progress report checks (with or without a user callback): the work stops
// by the exception `Interrupted`, as any progress function's exception stops it, and the caller gets
// KeyboardInterrupt. Python's handler is back when the call returns; a Ctrl-C the work never saw is handed to it
// (PyErr_SetInterrupt), so it is not lost.
#pragma once

#include <pybind11/pybind11.h>

#include <exception>
#include <functional>

namespace geartopo::python {

/// The work stopped by Ctrl-C; turned into KeyboardInterrupt (bind_errors).
struct Interrupted : std::exception {
  const char* what() const noexcept override { return "interrupted (Ctrl-C)"; }
};

/// SIGINT caught by geartopo while it lives (nested and concurrent calls share one installation).
class InterruptScope {
public:
  InterruptScope();
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
};

/// Throws Interrupted when Ctrl-C was pressed during the current call. Safe from any thread, without the GIL.
void throw_if_interrupted();

/// throw_if_interrupted as a library's keep_going check (grinding::SimulationOptions::keep_going): work that reports
/// progress too seldom (a flank of a fine grid takes minutes) checks for Ctrl-C from its inner loops.
inline std::function<void()> interrupt_check() {
  return [] { throw_if_interrupted(); };
}

/// A Ctrl-C pressed before the library work began — while the arguments were read, with the GIL held and Python's
/// handler in place (a measurement of 10⁵ points takes a tenth of a second) — is only the interpreter's flag, which
/// it would read once the whole call returned: raised here as KeyboardInterrupt, before the work starts.
struct EarlierInterrupt {
  EarlierInterrupt() {
    if (PyErr_CheckSignals() != 0) throw pybind11::error_already_set();
  }
};

/// A long call's library work: SIGINT caught by geartopo, a Ctrl-C from before then raised, the GIL released
/// (destroyed in the reverse order: the GIL taken back before Python's handler returns). The check comes after our
/// handler is in place, so a signal is either in Python's flag already or reaches ours.
struct LibraryWork {
  InterruptScope sigint;
  EarlierInterrupt earlier;
  pybind11::gil_scoped_release nogil;
};

} // namespace geartopo::python
