// geartopo — the report of a production series (docs/series.md, "The report"): one offline index.html with the series'
// header, the per-gear table (residuals, ISO class, pitch and runout), the findings across the series (the law of each
// quantity with σ, the next gear predicted, when the drawing's class is expected to be lost: the re-dress /
// re-compensation interval), the run charts and the synthetic closed-loop figure. Units: µm, h, strokes.
#pragma once

#include "geartopo/report/html_report.hpp"
#include "geartopo/series/series_analysis.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::report {

/// The figures the series command wrote into the report's folder (file names relative to it).
struct SeriesFigures {
  std::vector<std::filesystem::path> run_charts;      ///< run_chart_<key>.png, in the order of r.quantities
  std::optional<std::filesystem::path> closed_loop;   ///< closed_loop_synthetic.png
};

/// index.html of the series into `dir` (atomically).
void write_series_report(const std::filesystem::path& dir, const workbench::Workbench& wb, const series::SeriesResult& r,
                         const SeriesFigures& figures, const ReportOptions& options = {});

} // namespace geartopo::report
