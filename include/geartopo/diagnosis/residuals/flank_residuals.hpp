// geartopo diagnosis — the input of the residual analysis (`geartopo compare`, docs/residual-patterns.md): the
// residual (measured − model) of one measured flank, and a fitted value with its standard error.
//
// Units: roll length ξ (profile direction, root → tip) and axial position z (from the datum face, into the gear) in
// mm; residuals (measured − model), pattern heights, standard errors and the noise level σ in µm along the flank
// normal, plus material positive; wavelengths in mm; angles and phases in rad.
//
// Evaluation ranges: every flank carries its L_α = [ξ0, ξ1] and L_β = [z0, z1]. Points outside them (by more than
// evaluation::kRangeSlackMm, 1 µm, the slack of every evaluation range) are left out of everything here and counted;
// normalised coordinates are u = 2(ξ − ξ0)/(ξ1 − ξ0) − 1 and w = 2(z − z0)/(z1 − z0) − 1, both in [−1, 1].
//
// Every function of the residual analysis (flank_patterns.hpp, tooth_trends.hpp, failing_regions.hpp,
// residual_summary.hpp) throws std::invalid_argument with a message naming the reason for invalid input: non-finite
// values, no points, empty or non-finite ranges, tooth < 1, σ ≤ 0, or too few points to determine what is asked.
#pragma once

#include "geartopo/core/flank.hpp"

#include <vector>

namespace geartopo::diagnosis {

using geartopo::to_string; // Flank (core/flank.hpp), next to the to_string overloads of the residual analysis

/// One residual value on a flank.
struct ResidualPoint {
  double xi_mm = 0.0;       ///< roll length ξ (mm), increasing towards the tip
  double z_mm = 0.0;        ///< axial position (mm from the datum face)
  double residual_um = 0.0; ///< measured − model (µm, along the flank normal, plus material positive)
};

/// The residual of one measured flank. Points may be scattered; they often form the 7 × 9 grid.
struct FlankResiduals {
  int tooth = 1; ///< 1..z
  Flank side = Flank::Right;
  std::vector<ResidualPoint> points;
  double xi_start_mm = 0.0; ///< L_α start ξ0 (root end)
  double xi_end_mm = 0.0;   ///< L_α end ξ1 (tip end), ξ1 > ξ0
  double z_start_mm = 0.0;  ///< L_β start z0 (datum-face end)
  double z_end_mm = 0.0;    ///< L_β end z1 (far-face end), z1 > z0
};

/// A fitted value with its standard error (same unit), computed from the caller's σ and the design matrix.
struct Estimate {
  double value = 0.0;
  double standard_error = 0.0;
};

} // namespace geartopo::diagnosis
