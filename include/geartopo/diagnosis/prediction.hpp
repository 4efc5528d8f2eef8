// geartopo — the model's deviation at measured points (µm), by the simulator: the wheel's envelope (exact) or its
// first-order deviation (linear) at each point's own tooth, flank, roll length and axial position.
#pragma once

#include "geartopo/diagnosis/measured_points.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/grinding/grinding_setup.hpp"

#include <vector>

namespace geartopo::diagnosis {

/// Exact: throws std::runtime_error naming the first point (in input order) the wheel never reaches.
std::vector<double> predict(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& process,
                            const std::vector<MeasuredPoint>& points, grinding::Method method, int threads = 0);

} // namespace geartopo::diagnosis
