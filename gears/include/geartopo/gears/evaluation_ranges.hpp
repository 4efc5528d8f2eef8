// geartopo — where on a flank deviations are evaluated (ISO 1328-1:2013 clause 3.2/3.3 as documented in
// docs/iso1328.md). Units: mm (roll length ξ and axial position z from the datum face).
//
// Without a mating gear the active profile runs from the root form diameter d_Ff (SAP) to the tip diameter d_a (EAP,
// no tip chamfer). The profile evaluation range L_α is the first 95 % of the active length L_AE from the SAP; the
// helix evaluation range L_β is the face width less, at each end, the smaller of 5 % of b and one module.
#pragma once

#include "geartopo/gears/gear_geometry.hpp"

namespace geartopo::gears {

struct EvaluationRanges {
  double xi_active_start_mm = 0.0, xi_active_end_mm = 0.0; ///< L_AE: roll lengths of SAP and EAP (mm)
  double xi_eval_start_mm = 0.0, xi_eval_end_mm = 0.0;     ///< L_α: roll lengths (mm)
  double z_eval_start_mm = 0.0, z_eval_end_mm = 0.0;       ///< L_β: axial positions from the datum face (mm)
  double profile_evaluation_length() const { return xi_eval_end_mm - xi_eval_start_mm; }
  double helix_evaluation_length() const { return z_eval_end_mm - z_eval_start_mm; }
};

EvaluationRanges iso1328_ranges(const GearGeometry& g);

} // namespace geartopo::gears
