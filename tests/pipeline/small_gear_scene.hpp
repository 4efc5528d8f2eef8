// geartopo tests — the small helical gear the Monte Carlo tests share (m_n 4 mm, z 20, β 20°, b 30 mm: fast to
// simulate), on a 5×5 grid with 15-point traces. Units: as the scene keys say (mm, deg).
#pragma once

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/workbench/workbench.hpp"

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

/// Constant map errors of a few µm and tens of µrad (machine section lines): a machine worth compensating.
inline const std::string kSmallGearMapErrors =
    "  constants: {S_xz_urad: 30, E_XOC_um: 5, delta_xx_um: 4, epsilon_zx_urad: 40, E_YOC_um: 6}\n";

/// The flank method's corrections of a scene, every 2 mm.
inline compensation::CorrectionTable nominal_corrections(const workbench::Workbench& wb) {
  compensation::CompensationOptions co;
  co.step_mm = 2.0;
  return compensation::compute_corrections(wb.setup, wb.process(), {wb.machine, wb.scene.machine.datum_face_z_mm}, co);
}

/// The scene's grid and traces as simulation options.
inline grinding::SimulationOptions grid_of(const workbench::Workbench& wb) {
  grinding::SimulationOptions so;
  so.rows = wb.scene.grid.rows;
  so.cols = wb.scene.grid.cols;
  so.profile_points = wb.scene.grid.profile_points;
  so.helix_points = wb.scene.grid.helix_points;
  return so;
}

} // namespace geartopo::test
