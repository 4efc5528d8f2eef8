// geartopo synth TRUTH --out F|DIR/: a synthetic measurement of a gear ground on a truth scene (topology CSV, traces
// CSV or a Klingelnberg export; µm), with Gaussian probe noise, each stroke's scatter and a compensate run's
// corrections if asked.
#pragma once

#include <cstdint>
#include <string>

namespace geartopo::app {

struct SynthFlags {
  std::string scene, out, teeth = "1,18", format = "csv", corrections;
  double noise = 0.5;
  std::uint64_t seed = 1;
  bool stroke_scatter = false;
};

/// The command's work once its flags are parsed (synth_command.cpp); returns the exit code.
int run_synth(const SynthFlags& opt);

} // namespace geartopo::app
