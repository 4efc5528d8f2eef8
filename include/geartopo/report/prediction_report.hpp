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

/// "the rounding to machine.resolution", "repeatability", … for a pipeline::limit_sources name.
std::string source_label(const std::string& source);

/// How the samples were computed: "samples: linear (first order, checked: 4 exact samples within 0.0017 µm in every µm
/// quantity (threshold 0.05 µm), 0.0034 µm at every point)", or exact and why.
std::string sampling_line(const pipeline::MonteCarloSummary& s);

/// Which source sets the class after compensation (pipeline::after_limit), one line: "limit after compensation: …";
/// empty when not measured.
std::string limit_line(const pipeline::MonteCarloSummary& s);

/// One line per quantity: label, before band, after band — ISO quantities first, then largest |deviation|,
/// thickness and rotation on their own lines; the header names the coverage and the number of samples; then
/// sampling_line and limit_line.
std::vector<std::string> prediction_lines(const pipeline::MonteCarloSummary& s);

/// {"samples", "seed", "coverage_probability", "interval", "model", "iso_options": {"iso_direction",
/// "helix_slope_sign"} (the words of the CLI flags), "probe_noise_um", "quantities": {name: {"before": {"median", "low", "high"},
/// "after": {…}}}, "sampling": {"method", "reason", "checked_samples", "largest_point_difference_um",
/// "largest_quantity_difference_um", "threshold_um"}, "limit": {"dominant", "overall_class_after", "limiting_quantity",
/// "limiting_median_after_um", "without": {source: {"overall_class", "limiting_median_um", "quantities": {name: band}}}}
/// (only with linear samples)}; names carry their unit (_um, _class).
nlohmann::json prediction_json(const pipeline::MonteCarloSummary& s);

/// Reads what prediction_json wrote (prediction.json of `geartopo compensate`/`merge`): the samples, the seed, the ISO
/// options (std::nullopt in a file written before they were recorded), the probe noise (0 when absent) and each
/// quantity's bands. Throws InputError naming the file and the field (e.g. "quantities.F_p_um.after.low") for a file
/// that is not such JSON, a missing or non-finite number, or a band whose low > median or median > high.
pipeline::MonteCarloSummary read_prediction_json(const std::filesystem::path& file);

/// One measured quantity beside its prediction: inside when low ≤ measured ≤ high (µm).
struct PredictionCheck {
  std::string name;  ///< as the prediction names it, with its unit ("F_p_um")
  double measured_um = 0.0;
  pipeline::Band band;
  bool inside = false;
};

/// The quantities of `measured` that the prediction holds — µm quantities; largest |deviation| only when
/// `with_largest` (a traces measurement has no grid to take it from); no classes — against the predicted band of
/// `side` ("before": the uncorrected gear, "after": the compensated one), in the measurement's order.
std::vector<PredictionCheck> check_against_prediction(const pipeline::GearQuantities& measured,
                                                      const pipeline::MonteCarloSummary& prediction,
                                                      const std::string& side, bool with_largest);

/// A header line, then per check: label, measured value, predicted median [95 % interval], "inside" or "outside
/// (below/above)"; then "n of m inside their 95 % intervals".
std::vector<std::string> prediction_check_lines(const std::vector<PredictionCheck>& checks,
                                                const pipeline::MonteCarloSummary& prediction, const std::string& side);

/// {"side", "samples", "inside", "outside", "quantities": {name: {"measured", "median", "low", "high", "inside"}}}.
nlohmann::json prediction_check_json(const std::vector<PredictionCheck>& checks,
                                     const pipeline::MonteCarloSummary& prediction, const std::string& side);

/// prediction.png: per ISO quantity the before and after medians with their 95 % intervals, µm (section "compensation").
Figure prediction_figure(const pipeline::MonteCarloSummary& s, const std::filesystem::path& dir);

/// `png`: prediction.png's chart with measured gears marked on it — `before` (gear 1, ground without the corrections)
/// on the before whiskers, `after` (gear 2) on the after ones; either may be empty. Throws as render_bar_chart.
void prediction_check_figure(const pipeline::MonteCarloSummary& s, const std::vector<PredictionCheck>& before,
                             const std::vector<PredictionCheck>& after, const std::filesystem::path& png);

} // namespace geartopo::report
