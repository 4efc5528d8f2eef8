// geartopo — the closed loop over a series (docs/series.md, "The closed loop"): after gear k is measured, the
// across-series laws (drift_model.hpp) are fitted to gears 1 … k and gear k + 1 is ground with the correction that
// cancels the value they predict for it; the error falls as the laws are learnt. Synthetic: the truth (what the process
// leaves on the quantity without corrections) and the gear-to-gear scatter are given, the scatter drawn with a seed.
// A correction is assumed to act on the quantity one to one (a flank offset by an infeed or Z correction). Units: µm.
#pragma once

#include "geartopo/series/drift_model.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::series {

struct ClosedLoopInput {
  std::vector<GearState> states;                      ///< per gear, in the order ground
  std::function<double(const GearState&)> truth_um;   ///< the quantity without corrections at a gear's state
  double scatter_um = 0.0;                            ///< σ of the gear-to-gear scatter drawn on every gear (≥ 0)
  double floor_um = 1e-3;                             ///< the fits' scatter floor (fit_series)
  std::uint64_t seed = 1;
};

struct ClosedLoopGear {
  double open_um = 0.0;       ///< without corrections: truth + scatter
  double correction_um = 0.0; ///< applied while this gear was ground: −(value predicted from the gears before it)
  double closed_um = 0.0;     ///< with it: open + correction (the same scatter drawn)
  std::string model;          ///< the law the prediction came from ("" for gear 1: nothing known yet)
};

/// Gear 1 is ground without correction. From gear 2 on, the prediction is the mean of the gears so far while fewer than
/// 3 are known (fit_series needs 3), then the chosen law's median (predict). The gears' values as the loop sees them
/// are the measured ones minus their known correction (the uncorrected process), so that the laws see the drift alone.
/// Throws std::invalid_argument for no gear, no truth or a scatter < 0.
std::vector<ClosedLoopGear> run_closed_loop(const ClosedLoopInput& input);

} // namespace geartopo::series
