#include "geartopo/grinding/grinding_setup.hpp"

namespace geartopo::grinding {

GrindingSetup::GrindingSetup(const gears::GearSpec& gear, const WheelSpec& wheel, const ProcessSpec& process)
    : geometry_(gear), flanks_(geometry_), ranges_(gears::iso1328_ranges(geometry_)),
      setting_(make_wheel_setting(geometry_, wheel.outer_diameter_mm, wheel.axial_position_mm)),
      wheel_(geometry_, setting_, gears::FlankDesign(geometry_, ranges_, gear.modifications)),
      // The wheel touches z ∈ [0, b] while Z runs from −max z_c to b − min z_c.
      path_(geometry_, setting_, process, -wheel_.max_contact_offset_mm(),
            gear.face_width_mm - wheel_.min_contact_offset_mm()) {}

} // namespace geartopo::grinding
