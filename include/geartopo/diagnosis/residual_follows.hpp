// geartopo — what the residual follows, before any model is fitted (docs/diagnosis.md, "What the residual follows"):
// its dependence on the process variables of each measured point's generation — the time the wheel ground it, the
// stroke's place in the grinding order, the stroke position Z, the C angle (once per revolution) and the wheel radius
// at the contact. Each is fitted alone, with the set-up terms (thickness, rotation) fitted alongside so that an offset
// never reads as a trend; its strength is the ΔBIC against no dependence and the share of the residual it explains.
// Units: µm, and each variable's own (min, strokes, mm, °).
#pragma once

#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/measurement/measured_points.hpp"

#include <string>
#include <vector>

namespace geartopo::diagnosis {

struct ProcessDependence {
  std::string variable;  ///< "grinding time", "stroke order", "stroke position Z", "C angle", "wheel radius"
  std::string unit;      ///< the variable's unit: "min", "stroke", "mm", "deg"
  bool once_per_revolution = false; ///< the C angle: a·cos(γ − φ) instead of a slope
  double slope_um = 0.0, slope_sd_um = 0.0; ///< µm per unit of the variable (the amplitude a for the C angle), 1σ
  double phase_deg = 0.0, phase_sd_deg = 0.0; ///< C angle only: φ, where the residual is largest, and its 1σ
  double explained_fraction = 0.0;     ///< of the residual's sum of squares with the set-up terms removed (0 … 1)
  double delta_bic = 0.0;              ///< n ln(RSS/RSS₀) + p ln n against no dependence (unit-free)
  bool significant = false;            ///< ΔBIC below −threshold
  double lo = 0.0, hi = 0.0;           ///< the variable's range over the points (its unit)
  std::vector<double> values;          ///< per point, the variable (its unit): what a plot puts on its x axis
  std::string sentence;                ///< "grinding time: +0.62 ± 0.02 µm/min (ΔBIC −320, 54 % of the residual)"
};

struct ResidualFollows {
  std::vector<ProcessDependence> variables;       ///< strongest (lowest ΔBIC) first
  std::vector<double> residual_setup_removed_um;  ///< per point: what the fits see (µm), for plots
};

/// Every process variable's dependence. `residual_um`: measured − model per point (n). A variable that does not vary
/// over the points (one stroke: one stroke order) is left out. Throws std::invalid_argument for fewer than 4 points
/// or a residual of another length.
ResidualFollows residual_dependence(const grinding::GrindingSetup& setup,
                                                   const std::vector<measurement::MeasuredPoint>& points,
                                                   const std::vector<double>& residual_um, double bic_threshold = 10.0,
                                                   int threads = 0);

} // namespace geartopo::diagnosis
