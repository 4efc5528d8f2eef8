// What the series' figures share (private to geartopo_series): the drawn tolerance of a quantity.
#pragma once

#include "geartopo/render/charts.hpp"
#include "geartopo/series/series_analysis.hpp"

#include <optional>

namespace geartopo::series {

/// The drawing's tolerance of `q` as a shaded band: ±T for the slopes and the thickness allowance, 0 … T for the
/// quantities compared by size; none without a limit.
std::optional<render::Band> tolerance_band(const SeriesQuantity& q, const SeriesResult& r);

} // namespace geartopo::series
