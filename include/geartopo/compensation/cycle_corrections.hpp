// geartopo — axis corrections in the form a profile grinder's cycle takes them (docs/compensation.md): per tooth space
// an index correction of C, and lead corrections X(Z), C(Z) on an equidistant grid of machine Z; the Y and A
// corrections, which the cycle holds fixed over a gear, as set-up constants, with what that cannot carry reported.
//
// Built from a CorrectionTable (one row per path sample, five corrections). On a helical gear a Z correction is a C
// correction: moving the wheel along the gear's screw (Z by s, C by −k·s, k = 2 tan β / d the twist) leaves the flank
// unchanged, so (δZ, εC) acts on the flank as (0, εC + k·δZ). The lead table therefore carries C_eq = εC + k·δZ and no Z.
// On another chain (the table's ChainAxes) the same screw moves the chain's axes by σ per mm (J_twistw_θ·σ = the
// screw's twist; on the CAFXZY σ = (0, sin α, cos α, 0, −k)). The stroke axis S is the linear axis with the largest
// |σ_S| (the smallest at any row): each row's Δθ becomes Δθ − (δS/σ_S)·σ, whose S is 0; the lead axis is the other
// linear axis that moves most per mm of centre distance, the set-up axis the third (docs/compensation.md). On the
// CFXZAY, CAFXZY and CXFZAY S is Z, lead X, set-up Y; on a chain whose pose slot Z is another axis (a radial U) they
// follow the geometry, not the slots.
// Units: mm and rad inside; the file writes µm and µrad, machine Z in mm.
#pragma once

#include "geartopo/compensation/correction_table.hpp"

#include <array>
#include <filesystem>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

namespace geartopo::compensation {

struct CycleSpace {
  int space = 1;
  double index_dC_rad = 0.0;  ///< mean of C_eq over the stroke: the index correction of this space (rad)
  std::vector<double> z_mm;   ///< the stroke axis' machine position on the grid, increasing, equidistant (mm)
  std::vector<double> dX_mm;  ///< lead correction of the lead axis (X) at each grid point (mm)
  std::vector<double> dC_rad; ///< lead correction of C at each Z, C_eq − index_dC_rad (rad)
};

struct CycleCorrections {
  double z_step_mm = 0.0;         ///< grid step (mm), the requested step shortened to divide each stroke evenly
  double twist_rad_per_mm = 0.0;  ///< k used to fold δZ into C (rad/mm)
  std::string chain;              ///< the chain whose axes the fold follows; empty: the setting's axes (the CFXZAY)
  /// Pose slots of the cycle's linear axes: the stroke axis (the grid's argument, its correction folded away), the
  /// lead axis (per pose, X on the CFXZAY) and the set-up axis (once per gear, Y). The swivel (slot 3) is set up
  /// once, the spindle (slot 4) takes index + lead.
  int stroke_slot = 2, lead_slot = 0, setup_slot = 1;
  std::array<std::string, 5> axis_names{"X", "Y", "Z", "A", "C"}; ///< the chain's letters by pose slot
  double setup_dY_mm = 0.0;       ///< mean δ of the set-up axis (Y) over the whole path: one correction per gear (mm)
  double setup_dA_rad = 0.0;      ///< mean ε of the swivel (A) over the whole path (rad)
  double y_not_carried_mm = 0.0;  ///< largest |δY − setup_dY| along the path: what the cycle cannot apply (mm)
  double a_not_carried_rad = 0.0; ///< largest |εA − setup_dA| (rad)
  std::vector<CycleSpace> spaces; ///< in increasing space number

  /// The correction the machine applies at (space, stroke axis at machine position stroke_mm) with this cycle table:
  /// the lead axis' δ and C_eq interpolated linearly on the grid (held beyond its ends), the set-up axis and the
  /// swivel their constants, the stroke axis 0. In pose order, mm and rad.
  machine::Vector5d at(int space, double stroke_mm) const;
  /// at(row.space, the row's stroke axis position).
  machine::Vector5d at(const CorrectionRow& row) const;

  /// space,index_dC_urad,Z_mm,lead_dX_um,lead_dC_urad — one row per grid point — after comment lines (#) that state
  /// the conventions and the set-up constants (setup_dY_um, setup_dA_urad, not_carried_Y_um, not_carried_A_urad,
  /// z_step_mm, twist_rad_per_mm). The letters are the chain's (axis_names: Z the stroke axis, X the lead axis, Y the
  /// set-up axis, A the swivel, C the spindle). Example: docs/examples/cycle_corrections.csv.
  void write_csv(std::ostream& out) const;
  void write_csv(const std::filesystem::path& file) const;
};

/// No linear axis of the chain follows the gear axis by 0.1 mm per mm of the screw at every row: nothing can carry the
/// stroke and take its correction's fold (the cycle table is not made; `compensate` warns and writes the rest).
class NoStrokeAxis : public std::invalid_argument {
public:
  using std::invalid_argument::invalid_argument;
};

/// The cycle form of a correction table; z_step_mm > 0 is the largest grid step (each stroke gets at least 2 points).
/// Throws std::invalid_argument for an empty table or a step that is not positive and finite, NoStrokeAxis for a
/// chain none of whose linear axes moves by 0.1 mm or more per mm of the screw along the gear axis at every row.
CycleCorrections make_cycle_corrections(const CorrectionTable& table, double twist_rad_per_mm, double z_step_mm);

} // namespace geartopo::compensation
