#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/core/parallel.hpp"

#include <cmath>

namespace geartopo::diagnosis {

double mean_allowance_offset_um(const gears::GearGeometry& g) {
  const auto& s = g.spec();
  const double mean_allowance_mm = 0.5 * (s.thickness_allowance_upper_mm + s.thickness_allowance_lower_mm);
  return units::um_from_mm(mean_allowance_mm * std::cos(s.normal_pressure_angle_rad) / 2.0);
}

std::vector<double> predict(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& process,
                            const std::vector<MeasuredPoint>& points, grinding::Method method, int threads,
                            const std::function<void()>& keep_going) {
  const grinding::FlankDeviation dev(setup.flanks(), setup.wheel(), setup.path(), process);
  std::vector<double> out(points.size());
  const double offset_um = mean_allowance_offset_um(setup.geometry());
  // Chunks of points per task: one task per point would drown the work in scheduling.
  const int n = static_cast<int>(points.size()), chunk = 32;
  geartopo::parallel_for((n + chunk - 1) / chunk, threads, [&](int c) {
    if (keep_going && c % 128 == 0) keep_going(); // every 4096 points; parallel_for stops at the first exception
    for (int i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) {
      const auto& p = points[static_cast<size_t>(i)];
      out[static_cast<size_t>(i)] =
          units::um_from_mm(dev.at(p.tooth, p.flank, p.roll_length_mm, p.z_mm, method).deviation_mm) + offset_um;
    }
  });
  // The first-order model has no "not reached" (and the LM fits that call it reject non-finite steps themselves).
  if (method != grinding::Method::Exact) return out;
  const auto& g = setup.geometry();
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    grinding::require_reached(out[i], p.tooth, p.flank, g.diameter_at_roll_length(p.roll_length_mm), p.z_mm);
  }
  return out;
}

} // namespace geartopo::diagnosis
