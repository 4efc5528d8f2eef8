// geartopo — flank topologies (simulated or measured traces) as the ISO 1328-1 evaluator's input, and their
// evaluation: profile traces over L_α, helix traces over L_β, and for pitch and runout the deviation of each flank at
// mid face width on the helix-trace diameter (the middle of L_α). Units: µm, mm.
#pragma once

#include "geartopo/evaluation/gear_evaluation.hpp"
#include "geartopo/evaluation/tolerances.hpp"
#include "geartopo/evaluation/twist.hpp"
#include "geartopo/gears/evaluation_ranges.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/grinding/topology.hpp"

#include <vector>

namespace geartopo::workbench {

evaluation::GearParameters gear_parameters(const gears::GearGeometry& g);

/// How ISO values are reported (docs/iso1328.md): the direction and the f_Hβ sign rule; β_b comes from the gear.
struct IsoOptions {
  evaluation::IsoDirection direction = evaluation::IsoDirection::Transverse;
  evaluation::HelixSlopeSign helix_slope_sign = evaluation::HelixSlopeSign::HelixAngle;
};

/// The conventions of `o` for this gear (β_b signed by hand).
evaluation::IsoConventions iso_conventions(const gears::GearGeometry& g, const IsoOptions& o);

/// The evaluator's input: topology deviations are along the flank normal; `o` says how they are to be reported.
evaluation::GearMeasurement gear_measurement(const gears::GearGeometry& g, const gears::EvaluationRanges& r,
                                             const std::vector<grinding::FlankTopology>& topo, const IsoOptions& o = {});

struct FlankTwistResult {
  int tooth = 1;
  geartopo::Flank flank = geartopo::Flank::Left;
  evaluation::FlankTwist twist; ///< of the deviation from the design, along the flank normal (evaluation/twist.hpp)
};

struct IsoResult {
  evaluation::GearParameters parameters;
  evaluation::GearEvaluation evaluation;
  std::vector<FlankTwistResult> twists; ///< every flank with a grid (none from measured traces)
};

/// ISO 1328-1 values of the flanks, by default in the standard's (transverse) direction and sign rules.
IsoResult evaluate_iso(const gears::GearGeometry& g, const gears::EvaluationRanges& r,
                       const std::vector<grinding::FlankTopology>& topo, const IsoOptions& o = {});

} // namespace geartopo::workbench
