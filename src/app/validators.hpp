// geartopo — the checks of flag values shared by the commands (CLI11 validators): a value they refuse is bad usage
// (exit 2), named by its flag.
#pragma once

#include "geartopo/diagnosis/diagnose.hpp"

namespace CLI {
class Validator;
}

namespace geartopo::app {

/// A number within [lo, hi] and finite: CLI::Range lets NaN through (every comparison with NaN is false), so
/// `--noise-um nan` or `--step nan` passed the check. Refuses NaN, ±inf and values outside the range (exit 2).
CLI::Validator finite_in(double lo, double hi);
/// The probe noise σ a fit divides by (--noise-um of compare, diagnose, plan, report): finite and within
/// [kMinProbeSigmaUm, kMaxProbeSigmaUm] — diagnose's and compare's own bounds (diagnosis::kMinNoiseUm, kMaxNoiseUm, the
/// commands' check_noise_um); 1e-320 µm would make Σr²/σ² infinite in diagnosis.json and plan.json.
inline constexpr double kMinProbeSigmaUm = diagnosis::kMinNoiseUm, kMaxProbeSigmaUm = diagnosis::kMaxNoiseUm;
CLI::Validator probe_sigma_um();
/// A path that is not empty: `--out ""` wrote into the current folder's root ("" / "file" is "file"; "" as a folder
/// was created as nothing) instead of being refused.
CLI::Validator non_empty_path();
/// A seed: a whole number of 0 … 2⁶⁴ − 1 written with digits only. CLI11 reads "-1" into an unsigned seed as
/// 2⁶⁴ − 1 and 2⁶⁴ as 0; both are refused (exit 2) naming the flag.
CLI::Validator seed_value();

} // namespace geartopo::app
