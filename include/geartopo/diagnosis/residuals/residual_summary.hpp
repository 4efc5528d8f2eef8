// geartopo diagnosis — RMS and max |residual| per flank, tooth, side and overall (docs/residual-patterns.md,
// section 4). Units: µm (residuals), mm (ξ, z).
#pragma once

#include "geartopo/diagnosis/residuals/flank_residuals.hpp"

#include <cstddef>
#include <span>
#include <vector>

namespace geartopo::diagnosis {

struct ResidualStats {
  std::size_t points = 0;
  double rms_um = 0.0;     ///< √(Σ r²/N) over all pooled points
  double max_abs_um = 0.0; ///< max |r|
  double extreme_um = 0.0; ///< the signed r with max |r|
  int extreme_tooth = 0;
  Flank extreme_side = Flank::Right;
  double extreme_xi_mm = 0.0, extreme_z_mm = 0.0;
};
struct FlankStats {
  int tooth = 1;
  Flank side = Flank::Right;
  std::size_t points_outside_range = 0;
  ResidualStats stats;
};
struct ToothStats {
  int tooth = 1;
  ResidualStats stats; ///< both flanks pooled
};
struct SideStats {
  Flank side = Flank::Right;
  std::size_t flanks = 0;
  ResidualStats stats;
};
struct ResidualSummary {
  std::vector<FlankStats> flanks; ///< by tooth, left before right
  std::vector<ToothStats> teeth;  ///< ascending tooth
  std::vector<SideStats> sides;   ///< left, right (present sides only)
  ResidualStats overall;
};

/// RMS and max |residual| per flank, tooth, side and overall (points inside the evaluation ranges). Throws
/// std::invalid_argument for no flanks, a repeated (tooth, side) or an invalid flank.
ResidualSummary summarize_residuals(std::span<const FlankResiduals> flanks);

} // namespace geartopo::diagnosis
