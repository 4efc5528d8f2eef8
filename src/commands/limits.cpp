// geartopo — the bounds every front end enforces (limits.hpp).
#include "geartopo/commands/limits.hpp"

#include "geartopo/diagnosis/diagnose.hpp"

#include <fmt/format.h>

#include <cmath>
#include <set>

namespace geartopo::commands {

ArgumentError::ArgumentError(std::string argument, const std::string& expected)
    : std::invalid_argument(argument + ": " + expected), argument_(std::move(argument)) {}

void check_noise_um(double v, std::string_view argument) {
  if (v == 0.0) return;
  if (!(std::isfinite(v) && v >= diagnosis::kMinNoiseUm && v <= diagnosis::kMaxNoiseUm))
    throw ArgumentError(std::string(argument),
                        fmt::format("{} µm is not a probe noise σ: 0 (estimated) or {:g} … {:g} µm (below {:g} µm no "
                                    "probe measures, and the fit's Σr²/σ² would overflow)",
                                    v, diagnosis::kMinNoiseUm, diagnosis::kMaxNoiseUm, diagnosis::kMinNoiseUm));
}

void check_synthetic_noise_um(double v, std::string_view argument) {
  if (!(std::isfinite(v) && v >= 0.0 && v <= diagnosis::kMaxNoiseUm))
    throw ArgumentError(std::string(argument),
                        fmt::format("{} µm is not a noise σ: 0 (none) … {:g} µm", v, diagnosis::kMaxNoiseUm));
}

void check_samples(long long samples, std::string_view argument) {
  if (samples < 0 || samples > kMaxSamples)
    throw ArgumentError(std::string(argument),
                        fmt::format("{} is not a number of samples: 0 (nominal only) … {}", samples, kMaxSamples));
}

void check_grid(long long rows, long long cols, std::string_view argument) {
  if (rows < 1 || cols < 1 || rows > kMaxGridLines || cols > kMaxGridLines)
    throw ArgumentError(std::string(argument),
                        fmt::format("{} × {} is not a grid: rows and columns 1 … {} each", rows, cols, kMaxGridLines));
}

void check_path(const std::string& path, std::string_view argument) {
  if (path.empty()) throw ArgumentError(std::string(argument), "an empty path names no file");
  if (const auto nul = path.find('\0'); nul != std::string::npos)
    throw ArgumentError(std::string(argument),
                        fmt::format("the path holds a NUL character at {} ('{}' before it): no file is named so", nul,
                                    path.substr(0, nul)));
}

void check_teeth(const std::vector<int>& teeth, int z, std::string_view argument) {
  std::set<int> seen;
  for (int t : teeth) {
    if (t < 1 || t > z) throw ArgumentError(std::string(argument), fmt::format("{} is not a tooth of 1 … {}", t, z));
    if (!seen.insert(t).second) throw ArgumentError(std::string(argument), fmt::format("tooth {} is given twice", t));
  }
}

} // namespace geartopo::commands
