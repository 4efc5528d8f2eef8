#include "geartopo/pipeline/synth_corrections.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/core/random.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"

#include <fmt/format.h>

#include <set>
#include <utility>
#include <vector>

namespace geartopo::pipeline {

std::optional<compensation::CorrectionTable> synth_corrections(const workbench::Workbench& wb,
                                                               const std::string& corrections_file, bool stroke_scatter,
                                                               std::uint64_t seed) {
  if (corrections_file.empty() && !stroke_scatter) return std::nullopt;
  const int teeth = wb.setup.geometry().teeth();
  std::set<int> spaces;
  for (int s = 1; s <= teeth; ++s) spaces.insert(s);
  std::vector<compensation::CorrectionRow> zero_rows; // one row per space: held over the whole stroke
  for (const int s : spaces) {
    compensation::CorrectionRow r;
    r.space = s;
    zero_rows.push_back(r);
  }
  // In the scene's chain's axes (the setting's on the CFXZAY): a stroke offset is one axis' offset.
  const compensation::ChainAxes axes{wb.scene.machine.chain, wb.scene.machine.datum_face_z_mm};
  compensation::CorrectionTable table(std::move(zero_rows), axes);
  if (!corrections_file.empty()) {
    const auto read = compensation::CorrectionTable::read_csv(corrections_file, axes);
    // A table of another gear would leave spaces uncorrected (or correct spaces the gear does not have) in silence.
    std::set<int> in_file;
    for (const auto& r : read.rows()) in_file.insert(r.space);
    if (in_file != spaces)
      throw InputError(corrections_file, 0, 0, "space",
                       fmt::format("the table corrects spaces {}..{} ({} of them); the truth scene's gear has {} teeth: "
                                   "a corrections.csv of `geartopo compensate` on a scene of this gear is needed",
                                   *in_file.begin(), *in_file.rbegin(), in_file.size(), teeth));
    table = rounded_to_resolution(read, wb.scene.machine.uncertainty.resolution);
  }
  if (stroke_scatter) {
    // Its own stream, seeded by the first output of SplitMix64(seed): the probe noise draws from SplitMix64(seed) itself
    // (core/random.hpp; the same gear with every standard library).
    random::SplitMix64 gen(random::SplitMix64(seed).next());
    table = with_stroke_offsets(
        table, draw_stroke_offsets(spaces, wb.scene.machine.uncertainty.repeatability, [&] { return gen.normal(); }));
  }
  return table;
}

} // namespace geartopo::pipeline
