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

struct Figure {
  std::string file;    ///< relative to the report directory
  std::string section; ///< where it goes in the report
  std::string title;
  std::string caption;
  int width = 0, height = 0;
  std::optional<std::pair<double, double>> data_range_um;   ///< deviations shown (colour-mapped figures)
  std::optional<std::pair<double, double>> colour_range_um; ///< the colour scale used
  bool shared_scale = false; ///< the colour scale is another figure's on purpose (after uses before's)
};

/// Teeth the detailed figures show: the scene's measurement teeth, else 1 and the tooth half a turn away.
std::vector<int> focus_teeth(const workbench::Workbench& wb);

std::vector<Figure> render_figures(const workbench::Workbench& wb, const pipeline::PipelineResult& r, const std::filesystem::path& dir);

} // namespace geartopo::report
