// geartopo tests — the small helical gear the Monte Carlo tests share (m_n 4 mm, z 20, β 20°, b 30 mm: fast to
// simulate), on a 5×5 grid with 15-point traces. Units: as the scene keys say (mm, deg).
#pragma once

#include <string>

namespace geartopo::test {

/// The scene text; `machine_extra` (indented lines of the machine section: tables, constants, uncertainty …) is
/// appended to the machine section, which holds only the datum face otherwise.
inline std::string small_gear_scene_text(const std::string& machine_extra) {
  return "gear:\n"
         "  normal_module_mm: 4\n"
         "  teeth: 20\n"
         "  normal_pressure_angle_deg: 20\n"
         "  helix_angle_deg: 20\n"
         "  profile_shift: 0\n"
         "  face_width_mm: 30\n"
         "machine:\n"
         "  datum_face_z_mm: 300\n" +
         machine_extra +
         "wheel: {outer_diameter_mm: 300}\n"
         "measurement: {rows: 5, cols: 5, profile_points: 15, helix_points: 15}\n";
}

} // namespace geartopo::test
