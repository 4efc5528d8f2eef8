// geartopo — the "beyond the library" list as the console and the report show it: one row per equivalence class of the
// listed hypotheses (Candidate::equivalent), its other members listed in it, never ranked as separate findings with
// the same ΔBIC.
#pragma once

#include "geartopo/diagnosis/diagnose.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace geartopo::diagnosis {

struct HypothesisRow {
  const Candidate* hypothesis = nullptr; ///< the row's hypothesis (in Diagnosis::hypotheses)
  std::vector<std::string> members;      ///< the other members of its equivalence class, in order; empty: none
};

/// The rows of d.hypotheses in order, each hypothesis in an earlier one's class (Candidate::equivalent) folded into
/// that row.
std::vector<HypothesisRow> hypothesis_rows(const Diagnosis& d);

/// "one class with E_X0X constant, E_Y0X constant (the data cannot tell them apart)"; at most `shown` names, then how
/// many more (all in diagnosis.json, "equivalent"). Empty when the row has no members.
std::string members_text(const HypothesisRow& row, std::size_t shown = static_cast<std::size_t>(-1));

} // namespace geartopo::diagnosis
