// geartopo — ISO 1328-1 values as AQDEF characteristics (docs/aqdef.md): per tooth and flank F_α, f_fα, f_Hα, F_β,
// f_fβ, f_Hβ, and per gear f_p, F_p per flank side and F_r, each a characteristic with nominal 0, the drawing class's
// limits and one value per measured gear, with its time, batch and the gear's own id (K0014). Units: µm.
#pragma once

#include "geartopo/aqdef/aqdef.hpp"
#include "geartopo/evaluation/gear_evaluation.hpp"

#include <optional>
#include <string>
#include <vector>

namespace geartopo::series {

/// One measured gear's evaluation and when it was measured.
struct AqdefGear {
  const evaluation::GearEvaluation* evaluation = nullptr;
  std::optional<long long> time_epoch_s; ///< its job's start (shop time); none: no K0004
  std::string id;                        ///< the gear's serial number or id (K0014, ≤ 40 characters); empty: none
};

/// What the part's header says (K1001, K1002, K1082) and the batch every value carries (K0006; empty: none).
struct AqdefHeader {
  std::string part_number, part_description, machine, batch;
};

/// The characteristics of every tooth and flank any gear measured, in the order tooth, left before right, profile
/// then helix (F, f_f, f_H); then, when any gear has them (every tooth of a side measured), f_p and F_p of the left
/// and right flanks and F_r. A gear that did not measure one leaves no value there. Limits: ±T for the slopes, ≤ T
/// for the totals, forms, pitch and runout (no lower limit: 0 is their natural bound), T of `drawing_class`; none
/// without it.
aqdef::Part iso_aqdef(const std::vector<AqdefGear>& gears, const evaluation::GearParameters& parameters,
                      std::optional<int> drawing_class, const AqdefHeader& header);

} // namespace geartopo::series
