// geartopo effects, private — how many strokes a wheel has ground since it was last dressed, at a path point: the
// completed strokes (modulo the dressing interval) plus the running stroke's progress (wheel_wear,
// wheel_profile_wear).
#pragma once

#include "geartopo/grinding/grinding_setup.hpp"

#include <algorithm>
#include <cmath>

namespace geartopo::effects {

/// Strokes (≥ 0, fractional) since the last dressing; `interval` < 1: not dressed during the gear.
inline double strokes_since_dressing(const grinding::GrindingSetup& s, const grinding::PathPoint& pp, int interval) {
  const auto& path = s.path();
  double strokes = path.stroke_index(pp.space);
  if (interval > 0) strokes = std::fmod(strokes, interval);
  return strokes + std::clamp(path.stroke_progress(pp.space, pp.z_stroke_mm), 0.0, 1.0);
}

} // namespace geartopo::effects
