// geartopo — what compensation is predicted to gain, from the Monte Carlo prediction (pipeline/monte_carlo.hpp), never
// from the nominal after-state: the model corrected by itself is ≈ 0 by construction, so its "improvement" would be
// ≈ 100 % whatever the machine (a tautology). Units: µm, percent.
#pragma once

#include "geartopo/pipeline/monte_carlo.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace geartopo::report {

/// How every output names the nominal after-state, so that it is never read as a result.
inline constexpr const char* kNominalLabel = "nominal (the model corrected by itself)";
/// iso1328.json's `nominal_after_meaning`.
inline constexpr const char* kNominalAfterMeaning =
    "the model corrected by itself: the scene's machine ground with corrections computed from that same machine, "
    "~0 by construction; not what a machine known only within its uncertainties would grind (that is `prediction`)";

/// What `improvement` means in iso1328.json, the report and the console (docs/compensation.md, "Improvement").
inline constexpr const char* kImprovementDefinition =
    "100 (B - A) / B %, B the predicted median before compensation, A the predicted median after; its interval: the "
    "same with A at the ends of the after-state's 95 % interval (B held at its median). Sizes only (ISO values as "
    "|worst|, largest |deviation|); none where B <= 0.01 um. Without a prediction there is no improvement figure.";

/// One quantity's predicted improvement: 100 (B − A)/B with B the before-median and A the after-median (percent);
/// low/high: A at the after-interval's high/low end (so low ≤ percent ≤ high).
struct Improvement {
  std::string name; ///< as the prediction names it ("F_beta_um", "largest_abs_um")
  double before_median_um = 0.0;
  pipeline::Band after_um;
  double percent = 0.0, low_percent = 0.0, high_percent = 0.0;
};

/// The improvement of every size the prediction holds (µm quantities except the signed thickness and rotation), in
/// the prediction's order; a quantity whose before-median is ≤ 0.01 µm is left out (a percentage of nothing).
std::vector<Improvement> predicted_improvement(const pipeline::MonteCarloSummary& prediction);

/// Why a size is predicted worse after compensation (after-median above before-median), from the prediction's
/// decomposition by source (docs/monte-carlo.md, "What limits the gear after"): the source without which its
/// after-median falls most. `source` is empty when the samples carry no decomposition (exact samples).
struct Worsening {
  std::string name; ///< as the prediction names it ("f_falpha_um")
  double before_median_um = 0.0, after_median_um = 0.0;
  std::string source;                  ///< pipeline::limit_sources name, or "" (not measured)
  double without_source_median_um = 0.0; ///< the after-median without it
};

/// Every size of predicted_improvement whose after-median exceeds its before-median, in the prediction's order.
std::vector<Worsening> predicted_worsening(const pipeline::MonteCarloSummary& prediction);

/// "f_fα 0.13 → 0.15 µm: without the rounding to machine.resolution 0.07 µm — <what that source does>" (report,
/// console and iso1328.json say the same).
std::string worsening_text(const Worsening& w);

/// {"definition", "samples", "quantities": {name: {"before_median_um", "after_median_um", "after_low_um",
/// "after_high_um", "improvement_percent", "improvement_low_percent", "improvement_high_percent"[, "worse":
/// {"source", "after_median_without_source_um", "text"}]}}} — "worse" for a size predicted worse (predicted_worsening).
nlohmann::json improvement_json(const pipeline::MonteCarloSummary& prediction);

/// "F_β  −6 % [−33, +5]": a header naming the definition, then one line per quantity, then a line per size predicted
/// worse (worsening_text).
std::vector<std::string> improvement_lines(const pipeline::MonteCarloSummary& prediction);

/// "27 % [−33, 52]" (whole percent; the interval in brackets).
std::string improvement_text(const Improvement& i);
/// "27 [−33, 52]": the same without the unit (a table column named "(%)").
std::string improvement_number_text(const Improvement& i);

} // namespace geartopo::report
