// libFuzzer helpers: a reader may only throw its documented exception; anything else (another exception type, a
// crash, an ASan/UBSan report, a NaN in an accepted result) aborts and becomes a finding.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <typeinfo>

namespace geartopo::fuzz {

[[noreturn]] inline void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "FINDING: %s: %s\n", what, detail.c_str());
  std::abort();
}

inline void require_finite(double v, const char* what) {
  if (!std::isfinite(v)) finding("accepted a non-finite value", what);
}

// Runs fn; its documented exception type E is fine, every other exception is a finding.
template <class E, class Fn>
void run_expecting(Fn&& fn) {
  try {
    fn();
  } catch (const E&) {
  } catch (const std::exception& e) {
    finding((std::string("undocumented exception ") + typeid(e).name()).c_str(), e.what());
  } catch (...) {
    finding("non-std exception", "");
  }
}

} // namespace geartopo::fuzz
