// geartopo — the gear as drawn: designed flank modifications (ISO 21771:2007 flank modifications; a gear measuring
// machine evaluates against this design line, VDI/VDE 2607 practice) and the design topology they make
// (docs/modifications.md).
//
// Units: amounts in µm, diameters and lengths in mm; the profile coordinate is the roll length ξ (mm) and the helix
// coordinate the axial position z from the datum face (mm), as everywhere in geartopo.
//
// Sign: plus material positive, as deviations (docs/conventions.md). The design value is 0 on the bare involute
// helicoid and negative where the drawing removes material. Each term, on one flank:
//   profile crowning C_α:  −C_α (2(ξ − ξ_m)/L_α)²  — tangent to the involute in the middle ξ_m of L_α, C_α below it at
//                           both ends of L_α ("plus material in the middle"). The parabola stands for the circular arc
//                           of the drawing: they differ by C_α³/L_α² terms, below 10⁻⁶ µm for µm over mm.
//   profile slope f_Hα,d:  f (ξ − ξ_m)/L_α  — the design line rises by f from the start (root side) to the end (tip
//                           side) of L_α.
//   tip relief C_a:        −C_a t (linear) or −C_a t² (arc, tangent at its start), t = (ξ − ξ_Ca)/(ξ_a − ξ_Ca) for
//                           ξ > ξ_Ca: from the roll length ξ_Ca of the start diameter d_Ca to ξ_a at the tip diameter d_a.
//   root relief C_f:       the same towards the root form diameter: t = (ξ_Cf − ξ)/(ξ_Cf − ξ_Ff) for ξ < ξ_Cf.
//   helix crowning C_β:    −C_β (2(z − z_m)/L_β)², z_m the middle of L_β.
//   helix slope f_Hβ,d:    f (z − z_m)/L_β — rises by f towards +z (away from the datum face), whatever the hand.
//   end relief C_I = C_II: −C t or −C t² at both ends of the face width, t = (ℓ − distance to the end)/ℓ within the
//                           relief length ℓ of each end.
#pragma once

#include "geartopo/core/flank.hpp"

#include <string>
#include <vector>

namespace geartopo::gears {

class GearGeometry;
struct EvaluationRanges;

enum class ReliefShape { Linear, Arc };

/// The drawing's modifications of one flank (ISO 21771 terms; all 0: the bare involute helicoid).
struct FlankModifications {
  double profile_crowning_um = 0.0;            ///< C_α ≥ 0
  double profile_slope_um = 0.0;               ///< f_Hα,design
  double tip_relief_um = 0.0;                  ///< C_a ≥ 0
  double tip_relief_start_diameter_mm = 0.0;   ///< d_Ca (needed when C_a > 0)
  ReliefShape tip_relief_shape = ReliefShape::Linear;
  double root_relief_um = 0.0;                 ///< C_f ≥ 0
  double root_relief_start_diameter_mm = 0.0;  ///< d_Cf (needed when C_f > 0)
  ReliefShape root_relief_shape = ReliefShape::Linear;
  double helix_crowning_um = 0.0;              ///< C_β ≥ 0
  double helix_slope_um = 0.0;                 ///< f_Hβ,design
  double end_relief_um = 0.0;                  ///< C_I = C_II ≥ 0, both ends
  double end_relief_length_mm = 0.0;           ///< ℓ (needed when the end relief > 0)
  ReliefShape end_relief_shape = ReliefShape::Linear;

  /// True when any profile term (crowning, slope, reliefs) is not 0: the wheel is dressed with it.
  bool has_profile() const;
  /// True when any helix term (crowning, slope, end relief) is not 0: axis motions along the stroke make it.
  bool has_helix() const;
  bool empty() const { return !has_profile() && !has_helix(); }
  bool operator==(const FlankModifications&) const = default;
};

/// A designed topology given point by point (gear.modifications.table): per flank a full grid of diameters × axial
/// positions with the design value there (µm, plus material), added to the terms above. FlankDesign interpolates it
/// bilinearly in (ξ, z) and holds it constant beyond the grid's edges; the grid must cover L_α × L_β.
struct DesignTable {
  struct Grid {
    std::vector<double> diameter_mm, z_mm; ///< ascending
    std::vector<double> value_um;          ///< diameter-major: value_um[i · z_mm.size() + j]
    bool empty() const { return value_um.empty(); }
    bool operator==(const Grid&) const = default;
  };
  Grid left, right;
  std::string file; ///< the file it was read from (for messages)
  const Grid& of(geartopo::Flank f) const { return f == geartopo::Flank::Left ? left : right; }
  bool empty() const { return left.empty() && right.empty(); }
  bool operator==(const DesignTable&) const = default;
};

/// Both flanks' modifications (DIN ISO 21771 left/right flank, docs/conventions.md) and the designed table.
struct DesignModifications {
  FlankModifications left, right;
  DesignTable table;
  const FlankModifications& of(geartopo::Flank f) const { return f == geartopo::Flank::Left ? left : right; }
  bool empty() const { return left.empty() && right.empty() && table.empty(); }
  /// A profile part to dress into the wheel on flank f: a profile term, or the table (its values at the middle of L_β).
  bool has_profile(geartopo::Flank f) const { return of(f).has_profile() || !table.of(f).empty(); }
  /// A part the axis motions must grind: a helix term, or the table (what varies over z).
  bool has_helix() const { return left.has_helix() || right.has_helix() || !table.empty(); }
};

/// The design topology of a gear: the value of the drawing's modifications at every flank point (µm, plus material).
/// Immutable, shared by threads. Default-constructed: the bare involute helicoid (0 everywhere).
class FlankDesign {
public:
  FlankDesign() = default;
  /// Checks where the modifications start against the gear: a tip or root relief must start inside the active profile
  /// (d_Ff < d_C < d_a), an end relief must be shorter than half the face width, a table must cover L_α × L_β; throws
  /// FieldError naming "gear.modifications.<both|left|right>.<key>" (or ".table") and both numbers.
  FlankDesign(const GearGeometry& g, const EvaluationRanges& ranges, const DesignModifications& modifications);

  /// The profile part at roll length ξ (mm) → µm: crowning, slope, tip and root relief, and the table's values at the
  /// middle of L_β (the wheel is dressed with it).
  double profile_um(geartopo::Flank flank, double roll_length_mm) const;
  /// The helix part at z (mm from the datum face) → µm: crowning, slope, end relief (axis motions make it).
  double helix_um(geartopo::Flank flank, double z_mm) const;
  /// The design value at (ξ, z), µm: the terms, plus the table where there is one.
  double at_um(geartopo::Flank flank, double roll_length_mm, double z_mm) const {
    return profile_um(flank, roll_length_mm) + motion_target_um(flank, roll_length_mm, z_mm);
  }
  /// What the axis motions must leave at (ξ, z), µm: the design less its profile part (dressed into the wheel) — the
  /// helix terms, and the table's values less its values at the middle of L_β.
  double motion_target_um(geartopo::Flank flank, double roll_length_mm, double z_mm) const;
  /// The table's value at (ξ, z), µm (0 without a table for the flank).
  double table_um(geartopo::Flank flank, double roll_length_mm, double z_mm) const;

  const DesignModifications& modifications() const { return mods_; }
  bool empty() const { return mods_.empty(); }

private:
  struct Side {
    FlankModifications m;
    double xi_tip_relief = 0.0, xi_root_relief = 0.0; ///< ξ_Ca, ξ_Cf
    std::vector<double> table_xi_mm;                  ///< the table's diameters as roll lengths (empty: no table)
  };
  const Side& side(geartopo::Flank f) const { return f == geartopo::Flank::Left ? left_ : right_; }

  DesignModifications mods_;
  Side left_, right_;
  double xi_m_ = 0.0, l_alpha_ = 1.0, xi_ff_ = 0.0, xi_a_ = 1.0; ///< ξ_m, L_α, ξ at d_Ff and d_a
  double z_m_ = 0.0, l_beta_ = 1.0, face_ = 1.0;                ///< z_m, L_β, b
};

const char* to_string(ReliefShape shape);

} // namespace geartopo::gears
