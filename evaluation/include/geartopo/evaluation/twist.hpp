// geartopo — flank twist from a topology grid (docs/modifications.md): how the profile slope changes over the face
// width and the helix slope over the profile, as a helical gear crowned by radial infeed shows it.
//
//   profile twist S_α = f_Hα at the last grid column (the end of L_β away from the datum face) − f_Hα at the first;
//   helix twist   S_β = f_Hβ at the last grid row (the tip end of L_α) − f_Hβ at the first (root end),
// each slope the least-squares line's rise over its evaluation range (the design slopes' convention,
// gears/flank_modifications.hpp), in the grid's own direction (along the flank normal). Definitions after ISO 21771 /
// VDI/VDE 2607 practice as public sources describe them; the standards' texts were not read (docs/modifications.md).
// Units: µm, mm.
#pragma once

#include <vector>

namespace geartopo::evaluation {

struct TwistGridPoint {
  int row = 0, col = 0; ///< 1-based: rows over L_α from the root, cols over L_β from the datum face
  double roll_length_mm = 0.0, z_mm = 0.0, value_um = 0.0;
};

struct FlankTwist {
  double profile_twist_um = 0.0; ///< S_α
  double helix_twist_um = 0.0;   ///< S_β
};

/// S_α and S_β of one flank's grid (at least 2 rows and 2 columns; throws std::invalid_argument otherwise).
FlankTwist flank_twist(const std::vector<TwistGridPoint>& grid);

} // namespace geartopo::evaluation
