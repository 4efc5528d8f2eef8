// geartopo — the predicted after-state (pipeline/monte_carlo.hpp) as people and programs read it: bands
// "F_β 3.2 µm [1.9, 5.1] (95 %)", a JSON section with units in its keys, and a figure of medians and 95 % intervals
// drawn in µm (no magnification). Units: µm; classes are ISO 1328-1:2013 flank tolerance classes.
#pragma once

#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/report/figures.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace geartopo::report {

/// "F_β" for "F_beta_um", "class F_β" for "F_beta_class", "thickness", … (UTF-8, for people).
std::string quantity_label(const std::string& name);

/// "3.21 µm [1.90, 5.08]" (µm quantities) or "3 [2, 4]" (classes; "worse than 11" spelled out).
std::string band_text(const std::string& name, const pipeline::Band& b);

/// One line per quantity: label, before band, after band — ISO quantities first, then largest |deviation|,
/// thickness and rotation on their own lines; the header names the coverage and the number of samples.
std::vector<std::string> prediction_lines(const pipeline::MonteCarloSummary& s);

/// {"samples", "seed", "coverage_probability", "interval", "quantities": {name: {"before": {"median", "low", "high"},
/// "after": {…}}}}; names carry their unit (_um, _class).
nlohmann::json prediction_json(const pipeline::MonteCarloSummary& s);

/// The report's summary items (<li>…</li>): overall class and the ISO quantities before → after as bands, thickness
/// and rigid rotation on their own line.
std::string prediction_summary_html(const pipeline::MonteCarloSummary& s);

/// prediction.png: per ISO quantity the before and after medians with their 95 % intervals, µm (section "compensation").
Figure prediction_figure(const pipeline::MonteCarloSummary& s, const std::filesystem::path& dir);

} // namespace geartopo::report
