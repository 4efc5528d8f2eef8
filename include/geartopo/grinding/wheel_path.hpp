// geartopo — the wheel path: axis commands and time stamps along every stroke (docs/grinding.md).
//
// Tooth space s (1..z) lies between tooth s and tooth s+1; it holds the right flank of tooth s and the left flank of
// tooth s+1. Along a stroke the wheel travels in Z while C follows the lead (screw motion), so that the common
// perpendicular of wheel axis and gear axis stays on the space's centre line:
//   C(s, Z) = −θ_s(Z),   θ_s(Z) = (s − ½)·2π/z + (2 tan β / d)·Z,
// X, Y and A stay at the setting. Spaces are ground in the scene's order; each stroke runs over the face width plus
// the contact line's axial extent plus the overtravel at both ends, at the feed rate, with the indexing time between
// strokes. Units: mm, rad, s.
#pragma once

#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/grinding/wheel_setting.hpp"
#include "geartopo/machine/axis_pose.hpp"

#include <vector>

namespace geartopo::grinding {

enum class StrokeDirection { Up, Down, Alternate }; ///< Up: from the datum face (z = 0) towards z = b

/// How the helix modifications of the drawing (crowning, slope, end relief) are ground (docs/modifications.md):
/// RadialInfeed — X alone along the stroke (leaves twist on a helical gear); TwistFree — X, Y, Z, A and C along the
/// stroke, solved so that the flank takes the design.
enum class LeadCrowning { TwistFree, RadialInfeed };

struct ProcessSpec {
  double feed_mm_per_min = 1000.0; ///< axial feed along Z
  double overtravel_mm = 10.0;     ///< beyond the contact at both faces
  double indexing_time_s = 5.0;    ///< between two strokes
  int index_step = 1;              ///< 1: sequential; n > 1: skip indexing (gcd(n, z) must be 1)
  int first_space = 1;
  StrokeDirection direction = StrokeDirection::Up;
  LeadCrowning lead_crowning = LeadCrowning::TwistFree;
};

/// A point of the path: which space, where along the stroke, when, and the commanded axes.
struct PathPoint {
  int space = 1;
  double z_stroke_mm = 0.0; ///< Z command
  double time_s = 0.0;      ///< since the first stroke began
  machine::AxisPose q;      ///< commanded axes (C wrapped to [0, 2π))
};

struct Stroke {
  int space = 1;
  double z_begin_mm = 0.0, z_end_mm = 0.0; ///< in travel order (z_end < z_begin for a downward stroke)
  double t_begin_s = 0.0, t_end_s = 0.0;
};

class WheelPath {
public:
  /// z_lo, z_hi: Z range over which the wheel touches the face width (from the form wheel's contact line).
  WheelPath(const gears::GearGeometry& g, const WheelSetting& setting, const ProcessSpec& process, double z_lo_mm,
            double z_hi_mm);

  /// Commanded axes in space s at stroke position Z.
  machine::AxisPose commanded(int space, double z_stroke_mm) const;
  /// Time at which the wheel passes Z in space s (s); the stroke order and directions decide it.
  double time_at(int space, double z_stroke_mm) const;
  PathPoint point(int space, double z_stroke_mm) const;

  const std::vector<Stroke>& strokes() const { return strokes_; } ///< in grinding order
  /// Position of space s in the grinding order (0 for the first stroke).
  int stroke_index(int space) const { return order_of_space_[static_cast<size_t>(space - 1)]; }
  /// Fraction of its stroke the wheel has travelled at Z (0 at the start, 1 at the end, in travel order).
  double stroke_progress(int space, double z_stroke_mm) const;
  /// Direction of travel of space s's stroke: +1 towards z = b, −1 towards the datum face.
  int stroke_direction(int space) const;
  /// Samples every stroke at `step_mm` (ends included), in grinding order: the correction table's rows.
  std::vector<PathPoint> sample(double step_mm) const;

  const ProcessSpec& process() const { return process_; }
  const WheelSetting& setting() const { return setting_; }

private:
  int teeth_;
  double twist_;
  WheelSetting setting_;
  ProcessSpec process_;
  std::vector<Stroke> strokes_;
  std::vector<int> order_of_space_; ///< index into strokes_ for each space (0-based space)
};

} // namespace geartopo::grinding
