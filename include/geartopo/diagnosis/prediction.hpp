// geartopo — the model's deviation at measured points (µm), by the simulator: the wheel's envelope (exact) or its
// first-order deviation (linear) at each point's own tooth, flank, roll length and axial position.
#pragma once

#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/grinding/grinding_setup.hpp"

#include <functional>
#include <vector>

namespace geartopo::diagnosis {

using measurement::MeasuredPoint; ///< what diagnosis works on: measured points, read by the measurement library

/// The plus-material offset (µm, along the flank normal, the same on every flank) of the flank a gear is ground to at
/// the mean of its normal tooth-thickness allowances, against the zero-allowance nominal flank (docs/conventions.md,
/// "Nominal flank of a gear ground to an allowance"):
///   Δn = (A_sne + A_sni)/2 · cos α_n / 2
/// Negative for the usual negative allowances; 0 without allowances.
double mean_allowance_offset_um(const gears::GearGeometry& g);

/// The model's deviation at each point, referred to the nominal flank at the mean allowance: the simulated deviation
/// from the zero-allowance flank plus mean_allowance_offset_um, so that a gear ground to its allowances compares
/// without a constant offset.
/// Exact: throws std::runtime_error naming the first point (in input order) the wheel never reaches. `keep_going` (may
/// be empty) is called before every 4096 points (10⁶ points take seconds): a Ctrl-C check that may throw to stop.
std::vector<double> predict(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& process,
                            const std::vector<MeasuredPoint>& points, grinding::Method method, int threads = 0,
                            const std::function<void()>& keep_going = {});

} // namespace geartopo::diagnosis
