// geartopo — the bounds of what a caller may give geartopo, in one place: the libraries check them at their public
// entries (diagnose, compare, synthesize, simulate_topology, run_monte_carlo, run_pipeline, the measurement and series
// readers) and the front ends (commands/limits.hpp: the CLI's flags, the Python module's arguments) check the same
// bounds first, with the same messages, naming the argument as their caller calls it. Here, in the lowest library, so
// every library and both front ends see them and dependencies keep pointing one way. Units in every name.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::limits {

/// A probe noise σ a fit divides by (µm): 0 (estimated) or within [kMinNoiseUm, kMaxNoiseUm] — below 1e-6 µm no
/// probe measures and the fits' Σr²/σ² would overflow; above 1000 µm it is no measurement of a ground flank.
inline constexpr double kMinNoiseUm = 1e-6, kMaxNoiseUm = 1000.0;
/// The most Monte Carlo samples a run takes (10⁹ ended in std::bad_alloc).
inline constexpr long long kMaxSamples = 1'000'000;
/// The most rows or columns of a grid per flank.
inline constexpr long long kMaxGridLines = 1000;
/// The spacing of a correction table along each stroke (mm): the CLI's and the module's --step / step_mm.
inline constexpr double kMinStepMm = 0.05, kMaxStepMm = 50.0;
/// The most points of a profile or helix trace (the scene's measurement.profile_points, helix_points).
inline constexpr long long kMaxTracePoints = 100'000;

// Why a value is refused (what was expected, with the value and the range), or nullopt when it is accepted. The
// message names no argument: the caller prefixes its own name for it.

/// Probe noise σ of a fit: 0 or finite within [kMinNoiseUm, kMaxNoiseUm] µm.
std::optional<std::string> noise_um_refusal(double noise_um);
/// Noise σ a synthetic measurement draws with: finite within [0, kMaxNoiseUm] µm (0: none).
std::optional<std::string> synthetic_noise_um_refusal(double noise_um);
/// Monte Carlo samples: within [min_samples, kMaxSamples].
std::optional<std::string> samples_refusal(long long samples, long long min_samples = 0);
/// A grid of rows × cols per flank: each within [min_lines, kMaxGridLines].
std::optional<std::string> grid_refusal(long long rows, long long cols, long long min_lines = 1);
/// Points of a profile and of a helix trace: each within [2, kMaxTracePoints].
std::optional<std::string> trace_points_refusal(long long profile_points, long long helix_points);
/// A correction table's spacing: finite within [kMinStepMm, kMaxStepMm] mm.
std::optional<std::string> step_mm_refusal(double step_mm);
/// A path: not empty, and no NUL character (a C string would end there and name another file).
std::optional<std::string> path_refusal(std::string_view path);
/// Teeth: each within 1 … z, none twice (empty: the caller's default).
std::optional<std::string> teeth_refusal(const std::vector<int>& teeth, int z);

/// Throws std::invalid_argument("parameter: refusal") when there is a refusal: a library's check at its entry.
void require(const std::optional<std::string>& refusal, std::string_view parameter);

} // namespace geartopo::limits
