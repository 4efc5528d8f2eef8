// geartopo — the bounds every front end enforces on what it is given (the CLI's flags, the Python module's
// arguments): core/limits.hpp's bounds and messages, each check naming the argument as its caller calls it
// (`--noise-um`, `noise_um`). The libraries check the same bounds again at their public entries (core/limits.hpp),
// naming their parameter. Units in every name.
#pragma once

#include "geartopo/core/limits.hpp"

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::commands {

/// A value a front end was given that no command accepts, naming the argument (a flag or a keyword).
class ArgumentError : public std::invalid_argument {
public:
  ArgumentError(std::string argument, const std::string& expected);
  const std::string& argument() const { return argument_; }

private:
  std::string argument_;
};

/// The probe noise σ a fit divides by: 0 (estimate it from the residual) or finite within [1e-6, 1000] µm —
/// below 1e-6 µm no probe measures, and Σr²/σ² overflows (limits::kMinNoiseUm, kMaxNoiseUm).
void check_noise_um(double noise_um, std::string_view argument);
/// A noise σ a synthetic measurement draws with: 0 (none) or finite within (0, 1000] µm.
void check_synthetic_noise_um(double noise_um, std::string_view argument);
/// Monte Carlo samples: 0 (nominal only) … 10⁶ (count).
void check_samples(long long samples, std::string_view argument);
/// A grid of rows × cols per flank: each within 1 … 1000 (count).
void check_grid(long long rows, long long cols, std::string_view argument);
/// A path: not empty, and no NUL character (a C string would end there and name another file).
void check_path(const std::string& path, std::string_view argument);
/// Teeth: each within 1 … z, none twice (empty: the caller's default).
void check_teeth(const std::vector<int>& teeth, int z, std::string_view argument);

inline constexpr long long kMaxSamples = limits::kMaxSamples;
inline constexpr long long kMaxGridLines = limits::kMaxGridLines;

} // namespace geartopo::commands
