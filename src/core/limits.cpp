// geartopo — the bounds of what a caller may give geartopo (limits.hpp).
#include "geartopo/core/limits.hpp"

#include <fmt/format.h>

#include <cmath>
#include <set>

namespace geartopo::limits {

std::optional<std::string> noise_um_refusal(double v) {
  if (v == 0.0 || (std::isfinite(v) && v >= kMinNoiseUm && v <= kMaxNoiseUm)) return std::nullopt;
  return fmt::format("{} µm is not a probe noise σ: 0 (estimated) or {:g} … {:g} µm (below {:g} µm no probe "
                     "measures, and the fit's Σr²/σ² would overflow)",
                     v, kMinNoiseUm, kMaxNoiseUm, kMinNoiseUm);
}

std::optional<std::string> synthetic_noise_um_refusal(double v) {
  if (std::isfinite(v) && v >= 0.0 && v <= kMaxNoiseUm) return std::nullopt;
  return fmt::format("{} µm is not a noise σ: 0 (none) … {:g} µm", v, kMaxNoiseUm);
}

std::optional<std::string> samples_refusal(long long samples, long long min_samples) {
  if (samples >= min_samples && samples <= kMaxSamples) return std::nullopt;
  return fmt::format("{} is not a number of samples: {}{} … {}", samples, min_samples,
                     min_samples == 0 ? " (nominal only)" : "", kMaxSamples);
}

std::optional<std::string> grid_refusal(long long rows, long long cols, long long min_lines) {
  if (rows >= min_lines && cols >= min_lines && rows <= kMaxGridLines && cols <= kMaxGridLines) return std::nullopt;
  return fmt::format("{} × {} is not a grid: rows and columns {} … {} each", rows, cols, min_lines, kMaxGridLines);
}

std::optional<std::string> trace_points_refusal(long long profile_points, long long helix_points) {
  if (profile_points >= 2 && helix_points >= 2 && profile_points <= kMaxTracePoints && helix_points <= kMaxTracePoints)
    return std::nullopt;
  return fmt::format("{}, {} are not points of a trace: 2 … {} each", profile_points, helix_points, kMaxTracePoints);
}

std::optional<std::string> step_mm_refusal(double v) {
  if (std::isfinite(v) && v >= kMinStepMm && v <= kMaxStepMm) return std::nullopt;
  return fmt::format("{} mm is not a correction table's spacing: {:g} … {:g} mm", v, kMinStepMm, kMaxStepMm);
}

std::optional<std::string> path_refusal(std::string_view path) {
  if (path.empty()) return "an empty path names no file";
  if (const auto nul = path.find('\0'); nul != std::string_view::npos)
    return fmt::format("the path holds a NUL character at {} ('{}' before it): no file is named so", nul,
                       path.substr(0, nul));
  return std::nullopt;
}

std::optional<std::string> teeth_refusal(const std::vector<int>& teeth, int z) {
  std::set<int> seen;
  for (int t : teeth) {
    if (t < 1 || t > z) return fmt::format("{} is not a tooth of 1 … {}", t, z);
    if (!seen.insert(t).second) return fmt::format("tooth {} is given twice", t);
  }
  return std::nullopt;
}

void require(const std::optional<std::string>& refusal, std::string_view parameter) {
  if (refusal) throw std::invalid_argument(fmt::format("{}: {}", parameter, *refusal));
}

} // namespace geartopo::limits
