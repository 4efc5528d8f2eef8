// geartopo — why diagnose decided what it did, as data (docs/diagnosis.md, "The verdict as data"). Every decision the
// pipeline takes — a fit refused, a value no measurement, an explanation withheld, a machine element kept out — is a
// record: a reason code, what it is about, the other explanations it names and its numbers, each named with its unit.
// The sentences people read (console, report, the verdict, Python) are composed from these records in one place
// (verdict_text.cpp); diagnosis.json carries the records themselves under "decisions" (the schema is in the docs).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace geartopo::diagnosis {

enum class Reason {
  // Why a fit is no explanation (Candidate::rejection, Diagnosis::nearest_rejection).
  implausible_value,    ///< subject "effect.key": value, sd, plausible_lo, plausible_hi, at_end_of_range (0/1)
  implausible_change,   ///< subject a component: reach, limit (file units: µm or µrad, `unit`)
  implausible_wave,     ///< subject a wheel flank's waviness: amplitude_um, limit_um
  more_than_noise,      ///< what it leaves fails a χ² test: statistic, limit, dof, false_alarm; `test` total|surface
  not_significant,      ///< delta_bic, threshold
  explains_less,        ///< names[0]: the nearest explanation, itself no explanation
  // Why an explanation's single values are no measurement (the machine elements are then tried; withheld).
  at_end_of_range,      ///< subject "effect.key": value, lo, hi
  not_determined,       ///< subject "effect.key"
  parts_cancel,         ///< names: the parts; numbers part_rms_um (one per part, in order), together_rms_um
  // Why an explanation is not added to the scene.
  ambiguous,            ///< names: [chosen, best rival]
  // What the machine elements decided beside the library's explanation (names[0]).
  element_kept_out,     ///< subject: the element's description; delta_bic, threshold
  // What the measurement is measured from (before any fit).
  reference_in_doubt,   ///< subject "measurement": read as against the bare involute (nobody said), its residual minus
                        ///< the design: residual_rms_um, against_drawing_rms_um, design_rms_um, noise_um, share_limit
};

/// "implausible_value", "more_than_noise", … (diagnosis.json's "reason").
std::string_view to_string(Reason reason);

struct Decision {
  Decision() = default;
  Decision(Reason r, std::string what, std::vector<std::string> others = {},
           std::vector<std::pair<std::string, double>> values = {})
      : reason(r), subject(std::move(what)), names(std::move(others)), numbers(std::move(values)) {}

  Reason reason = Reason::not_significant;
  std::string subject;                                  ///< the explanation or "effect.parameter" it is about
  std::vector<std::string> names;                       ///< other explanations or parts it names, in order
  std::vector<std::pair<std::string, double>> numbers;  ///< its numbers, keys with their unit where they have one
  std::string unit;                                     ///< the unit of reach/limit (implausible_change): "µm", "µrad"
  std::string test;                                     ///< more_than_noise: "total" (Σr²/σ²) or "surface"

  /// The number named `key`; throws std::out_of_range when the record has none.
  double number(std::string_view key) const;
  /// All numbers named `key`, in order (parts_cancel's part_rms_um).
  std::vector<double> all(std::string_view key) const;
};

/// The sentence of a record, as the verdict, the console and the report print it.
std::string to_text(const Decision& d);

} // namespace geartopo::diagnosis
