#include "geartopo/grinding/wheel_path.hpp"

#include "geartopo/core/field_error.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <numeric>

namespace geartopo::grinding {

WheelPath::WheelPath(const gears::GearGeometry& g, const WheelSetting& setting, const ProcessSpec& p, double z_lo,
                     double z_hi)
    : teeth_(g.teeth()), twist_(g.twist_rad_per_mm()), setting_(setting), process_(p) {
  if (!(p.feed_mm_per_min > 0.0)) throw FieldError("process.feed_mm_per_min", "must be > 0");
  if (!(p.indexing_time_s >= 0.0)) throw FieldError("process.indexing_time_s", "must be >= 0");
  if (!(p.overtravel_mm >= 0.0)) throw FieldError("process.overtravel_mm", "must be >= 0");
  if (p.index_step < 1 || p.index_step >= teeth_ || std::gcd(p.index_step, teeth_) != 1)
    throw FieldError("process.index_step",
                     fmt::format("{} does not visit every space of a {}-tooth gear (needs 1 ≤ n < z and gcd(n, z) = 1)",
                                 p.index_step, teeth_));
  if (p.first_space < 1 || p.first_space > teeth_)
    throw FieldError("process.first_space", fmt::format("{} is not a tooth space of 1..{}", p.first_space, teeth_));

  const double lo = z_lo - p.overtravel_mm, hi = z_hi + p.overtravel_mm;
  const double stroke_time = (hi - lo) / (p.feed_mm_per_min / 60.0);
  order_of_space_.assign(static_cast<size_t>(teeth_), -1);
  double t = 0.0;
  for (int i = 0; i < teeth_; ++i) {
    const int space = (p.first_space - 1 + i * p.index_step) % teeth_ + 1;
    const bool up = p.direction == StrokeDirection::Up || (p.direction == StrokeDirection::Alternate && i % 2 == 0);
    Stroke s{space, up ? lo : hi, up ? hi : lo, t, t + stroke_time};
    order_of_space_[static_cast<size_t>(space - 1)] = static_cast<int>(strokes_.size());
    strokes_.push_back(s);
    t = s.t_end_s + p.indexing_time_s;
  }
}

machine::AxisPose WheelPath::commanded(int space, double z) const {
  const double theta = (space - 0.5) * 2.0 * std::numbers::pi / teeth_ + twist_ * z;
  double c = std::fmod(-theta, 2.0 * std::numbers::pi);
  if (c < 0.0) c += 2.0 * std::numbers::pi;
  return {setting_.centre_distance_mm, setting_.axial_position_mm, z, setting_.tilt_rad, c};
}

double WheelPath::time_at(int space, double z) const {
  const Stroke& s = strokes_[static_cast<size_t>(order_of_space_[static_cast<size_t>(space - 1)])];
  return s.t_begin_s + std::abs(z - s.z_begin_mm) / (process_.feed_mm_per_min / 60.0);
}

double WheelPath::stroke_progress(int space, double z) const {
  const Stroke& s = strokes_[static_cast<size_t>(stroke_index(space))];
  return (z - s.z_begin_mm) / (s.z_end_mm - s.z_begin_mm);
}

int WheelPath::stroke_direction(int space) const {
  const Stroke& s = strokes_[static_cast<size_t>(stroke_index(space))];
  return s.z_end_mm > s.z_begin_mm ? 1 : -1;
}

PathPoint WheelPath::point(int space, double z) const { return {space, z, time_at(space, z), commanded(space, z)}; }

std::vector<PathPoint> WheelPath::sample(double step_mm) const {
  std::vector<PathPoint> out;
  for (const Stroke& s : strokes_) {
    const double len = std::abs(s.z_end_mm - s.z_begin_mm);
    const int n = std::max(1, static_cast<int>(std::ceil(len / step_mm)));
    for (int i = 0; i <= n; ++i) out.push_back(point(s.space, s.z_begin_mm + (s.z_end_mm - s.z_begin_mm) * i / n));
  }
  return out;
}

} // namespace geartopo::grinding
