// geartopo — the corrections a synthetic measurement's gear is ground with (`geartopo synth --corrections F
// --stroke-scatter`, geartopo.synth in Python): those of a compensate run, rounded to the truth machine's command
// resolution as the controller takes them (the Monte Carlo's gear 2), each stroke's command scatter
// (machine.repeatability, drawn as every Monte Carlo sample draws it), both or neither (docs/monte-carlo.md).
#pragma once

#include "geartopo/compensation/correction_table.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace geartopo::pipeline {

/// std::nullopt when neither is asked for (corrections_file empty, no stroke scatter). The table holds one row per
/// space of the truth scene's gear; corrections_file must correct exactly those spaces (InputError naming the file
/// and "space" otherwise, as for any read error of the table). The stroke scatter draws from its own stream, seeded
/// by the first output of SplitMix64(seed): the probe noise of the same synth draws from SplitMix64(seed) itself.
std::optional<compensation::CorrectionTable> synth_corrections(const workbench::Workbench& wb,
                                                               const std::string& corrections_file, bool stroke_scatter,
                                                               std::uint64_t seed);

} // namespace geartopo::pipeline
