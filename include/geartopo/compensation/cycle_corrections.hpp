// geartopo — axis corrections in the form a profile grinder's cycle takes them (docs/compensation.md): per tooth space
// an index correction of C, and lead corrections X(Z), C(Z) on an equidistant grid of machine Z; the Y and A
// corrections, which the cycle holds fixed over a gear, as set-up constants, with what that cannot carry reported.
//
// Built from a CorrectionTable (one row per path sample, five corrections). On a helical gear a Z correction is a C
// correction: moving the wheel along the gear's screw (Z by s, C by −k·s, k = 2 tan β / d the twist) leaves the flank
// unchanged, so (δZ, εC) acts on the flank as (0, εC + k·δZ). The lead table therefore carries C_eq = εC + k·δZ and no Z.
// On another chain (the table's ChainAxes) the same screw moves the chain's axes by σ per mm (J_twistw_θ·σ = the
// screw's twist; on the CAFXZY σ = (0, sin α, cos α, 0, −k)): each row's Δθ becomes Δθ − (δZ/σ_Z)·σ, whose Z is 0,
// and its X, C, Y and A are what the cycle carries (docs/compensation.md).
// Units: mm and rad inside; the file writes µm and µrad, machine Z in mm.
#pragma once

#include "geartopo/compensation/correction_table.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace geartopo::compensation {

struct CycleSpace {
  int space = 1;
  double index_dC_rad = 0.0;  ///< mean of C_eq over the stroke: the index correction of this space (rad)
  std::vector<double> z_mm;   ///< machine Z of the grid, increasing, equidistant (mm)
  std::vector<double> dX_mm;  ///< lead correction of X at each Z (mm)
  std::vector<double> dC_rad; ///< lead correction of C at each Z, C_eq − index_dC_rad (rad)
};

struct CycleCorrections {
  double z_step_mm = 0.0;         ///< grid step (mm), the requested step shortened to divide each stroke evenly
  double twist_rad_per_mm = 0.0;  ///< k used to fold δZ into C (rad/mm)
  std::string chain;              ///< the chain whose axes the fold follows; empty: the setting's axes (the CFXZAY)
  double setup_dY_mm = 0.0;       ///< mean δY over the whole path: one Y correction for the gear (mm)
  double setup_dA_rad = 0.0;      ///< mean εA over the whole path (rad)
  double y_not_carried_mm = 0.0;  ///< largest |δY − setup_dY| along the path: what the cycle cannot apply (mm)
  double a_not_carried_rad = 0.0; ///< largest |εA − setup_dA| (rad)
  std::vector<CycleSpace> spaces; ///< in increasing space number

  /// The correction the machine applies at (space, machine Z) with this cycle table: δX and C_eq interpolated linearly
  /// on the grid (held beyond its ends), δY and εA the set-up constants, δZ = 0. As δX, δY, δZ (mm), εA, εC (rad).
  machine::Vector5d at(int space, double machine_z_mm) const;

  /// space,index_dC_urad,Z_mm,lead_dX_um,lead_dC_urad — one row per grid point — after comment lines (#) that state
  /// the conventions and the set-up constants (setup_dY_um, setup_dA_urad, not_carried_Y_um, not_carried_A_urad,
  /// z_step_mm, twist_rad_per_mm). Example: docs/examples/cycle_corrections.csv.
  void write_csv(std::ostream& out) const;
  void write_csv(const std::filesystem::path& file) const;
};

/// The cycle form of a correction table; z_step_mm > 0 is the largest grid step (each stroke gets at least 2 points).
/// Throws std::invalid_argument for an empty table, a step that is not positive and finite, or a chain whose Z
/// moves less than 0.1 mm per mm of the screw along the gear axis at a row (its δZ cannot be folded).
CycleCorrections make_cycle_corrections(const CorrectionTable& table, double twist_rad_per_mm, double z_step_mm);

} // namespace geartopo::compensation
