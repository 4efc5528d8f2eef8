// geartopo — the report's figures (PNG, off-screen through src/render): topology, traces, pitch, machine errors,
// before/after, measured vs model, diagnosis, the gear in 3D. Each figure records the data range it shows and the
// colour range it used, so that tests can check that colour scales span the data.
#pragma once

#include "geartopo/pipeline/pipeline.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::report {

/// What one deviation chart shows, in deviation µm (not mirrored): the scale test checks axis ⊇ data ∪ tolerance.
struct ChartRange {
  std::string panel;                             ///< panel file name (panels/)
  std::pair<double, double> data_um{0.0, 0.0};   ///< the trace's deviations
  std::pair<double, double> tolerance_um{0.0, 0.0}; ///< the tolerance box across (equal ends: none drawn)
  std::pair<double, double> axis_um{0.0, 0.0};   ///< the axis range drawn
  double min_span_um = 0.0;                       ///< the least span the scale was asked for (2 × F_T)
};

struct Figure {
  std::string file;    ///< relative to the report directory
  std::string section; ///< where it goes in the report
  std::string title;
  std::string caption;
  int width = 0, height = 0;
  std::optional<std::pair<double, double>> data_range_um;   ///< deviations shown (colour-mapped figures)
  std::optional<std::pair<double, double>> colour_range_um; ///< the colour scale used
  bool shared_scale = false; ///< the colour scale is another figure's on purpose (after uses before's)
  std::vector<ChartRange> charts{}; ///< deviation charts inside (trace figures)
  int tooth = 0;                  ///< the tooth a per-tooth figure shows (0: none)
};

/// The class whose tolerance boxes the trace charts draw: the scene's report.tolerance_class, else the achieved
/// overall class before compensation (clamped to 1..11), else 5.
int shown_tolerance_class(const workbench::Workbench& wb, const pipeline::PipelineResult& r);

/// Teeth the detailed figures show: the scene's measurement teeth, else 1 and the tooth half a turn away.
std::vector<int> focus_teeth(const workbench::Workbench& wb);

/// The figures of the gear before compensation (topology, traces, pitch, runout, machine errors, 3D gear): they need
/// r.before, r.iso_before and r.largest_before_um only, so `run` draws them on another thread while the pipeline goes
/// on (PipelineOptions::before_ready). The same files and pixels as render_figures draws.
std::vector<Figure> render_before_figures(const workbench::Workbench& wb, const pipeline::PipelineResult& r,
                                          const std::filesystem::path& dir);
/// Every figure of the report, in the page's order; `before`: what render_before_figures returned for this gear
/// (empty: drawn here).
std::vector<Figure> render_figures(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const std::filesystem::path& dir,
                                   std::vector<Figure> before = {});

} // namespace geartopo::report
