// geartopo — everything fixed before grinding starts: gear, flanks, evaluation ranges, wheel setting, form wheel and
// path. Built once, then read-only and shared by all threads (the "Model" of the simulator). Units: mm, rad, s.
#pragma once

#include "geartopo/gears/evaluation_ranges.hpp"
#include "geartopo/gears/flank_modifications.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/gears/involute_helicoid.hpp"
#include "geartopo/grinding/form_wheel.hpp"
#include "geartopo/grinding/wheel_path.hpp"
#include "geartopo/grinding/wheel_setting.hpp"

namespace geartopo::grinding {

struct WheelSpec {
  double outer_diameter_mm = 350.0;
  double axial_position_mm = 0.0; ///< Y
};

class GrindingSetup {
public:
  GrindingSetup(const gears::GearSpec& gear, const WheelSpec& wheel, const ProcessSpec& process);

  const gears::GearGeometry& geometry() const { return geometry_; }
  const gears::InvoluteHelicoid& flanks() const { return flanks_; }
  const gears::EvaluationRanges& ranges() const { return ranges_; }
  /// The drawing's design topology (gear.modifications): the wheel is dressed with its profile part, axis motions
  /// along the stroke make its helix part, and every deviation is measured against it.
  const gears::FlankDesign& design() const { return wheel_.design(); }
  const WheelSetting& setting() const { return setting_; }
  const FormWheel& wheel() const { return wheel_; }
  const WheelPath& path() const { return path_; }

private:
  gears::GearGeometry geometry_;
  gears::InvoluteHelicoid flanks_;
  gears::EvaluationRanges ranges_;
  WheelSetting setting_;
  FormWheel wheel_;
  WheelPath path_;
};

} // namespace geartopo::grinding
