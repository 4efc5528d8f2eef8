// geartopo — the run charts of a series (docs/series.md): each per-gear quantity over the gears with the drawing
// class's tolerance, its mean, its straight-line trend, the across-series law chosen and the next gear's 95 %
// interval. Off-screen PNGs through the render library. Units: µm.
#pragma once

#include "geartopo/series/series_analysis.hpp"

#include <filesystem>
#include <optional>
#include <vector>

namespace geartopo::series {

/// Writes run_chart_<key>.png into `dir` for every quantity with values at every gear; returns the files written.
std::vector<std::filesystem::path> write_run_charts(const SeriesResult& r, const std::filesystem::path& dir);

} // namespace geartopo::series

namespace geartopo::series {

/// The quantity the closed-loop figure follows: of those with a fitted law other than noise, the one whose law moves
/// most over the series (µm); else the tooth thickness. Nullopt when no quantity has a fit (fewer than 3 gears).
std::optional<std::size_t> closed_loop_quantity(const SeriesResult& r);

/// closed_loop_synthetic.png in `dir`: the closed loop (closed_loop.hpp) run on the series' own gear states, stepped on
/// to at least 12 gears, with the law fitted to closed_loop_quantity as the truth and its scatter drawn (seed 41) —
/// open loop against corrections from gear k's diagnosis applied to gear k + 1, with the drawing's tolerance. Labelled
/// synthetic in its title. Nullopt (nothing written) when no quantity has a fit.
std::optional<std::filesystem::path> write_closed_loop_figure(const SeriesResult& r, const std::filesystem::path& dir);

} // namespace geartopo::series
