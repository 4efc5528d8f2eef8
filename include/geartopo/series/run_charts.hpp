// geartopo — the run charts of a series (docs/series.md): each per-gear quantity over the gears with the drawing
// class's tolerance, its mean, its straight-line trend, the across-series law chosen and the next gear's 95 %
// interval. Off-screen PNGs through the render library. Units: µm.
#pragma once

#include "geartopo/series/series_analysis.hpp"

#include <filesystem>
#include <vector>

namespace geartopo::series {

/// Writes run_chart_<key>.png into `dir` for every quantity with values at every gear; returns the files written.
std::vector<std::filesystem::path> write_run_charts(const SeriesResult& r, const std::filesystem::path& dir);

} // namespace geartopo::series
