// geartopo — measured flank points: where they lie on the nominal flank and what was measured there.
// Units: mm, µm (deviation along the flank normal, plus material positive).
#pragma once

#include "geartopo/gears/evaluation_ranges.hpp"
#include "geartopo/gears/flank_modifications.hpp"
#include "geartopo/core/flank.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/grinding/topology_csv.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::measurement {

struct MeasuredPoint {
  int tooth = 1;
  geartopo::Flank flank = geartopo::Flank::Left;
  int row = 0, col = 0;          ///< grid indices if the file has them (topology CSV), else 0 (traces, clouds, exports)
  double roll_length_mm = 0.0;
  double diameter_mm = 0.0;
  double z_mm = 0.0;
  double deviation_um = 0.0;     ///< measured, from design_um
  double design_um = 0.0;        ///< the design the deviation is measured from: the file's (design_um column; 0 when
                                 ///< it has none: the bare involute), the scene's after read_any_measurement
  int line = 0;                  ///< line in the measurement file
  std::int64_t id = -1;          ///< a point cloud's id column (the measuring machine's point number); −1: none
  /// Whether anybody said what the deviation is measured from: a design_um column, or MeasuredAgainst::design or
  /// ::involute. False: a file without the column read as against the bare involute by default, which a machine that
  /// evaluates against the drawing also writes (diagnose checks for it: Reason::reference_in_doubt).
  bool reference_declared = true;
};

/// What a measurement's deviations are measured from (docs/modifications.md, "Measurements against the design"), for a
/// file that does not say it with a design_um column (`--measured-against`, `measurement.measured_against`).
enum class MeasuredAgainst {
  as_file,  ///< as the file says: its design_um column; without one the bare involute, undeclared
  design,   ///< the scene's drawing: a measuring machine that evaluates against the design (an export too)
  involute, ///< the bare involute, declared
};

/// "design", "involute" (as_file: "file"); the word a flag or scene key takes.
std::string_view to_string(MeasuredAgainst against);
/// The value of a word of to_string (design, involute), none for another word.
std::optional<MeasuredAgainst> parse_measured_against(std::string_view word);

/// Refers measured deviations to `design` (the scene's drawing): the measured flank is deviation_um + design_um of
/// the file; from the scene's design d it deviates by that less d. Files without a design column (design 0) are so
/// read as measured against the bare involute.
void refer_to_design(std::vector<MeasuredPoint>& points, const gears::FlankDesign& design);
void refer_to_design(std::vector<grinding::FlankTopology>& traces, const gears::FlankDesign& design);

/// Points of a topology file on the gear. A point outside the active profile (d_Ff … d_a, 1 µm slack) or the face
/// width is "off the flank": std::runtime_error naming file:line and the field.
std::vector<MeasuredPoint> measured_points(const std::vector<grinding::TopologyRow>& rows, const gears::GearGeometry& g,
                                           const std::string& source);

/// The same for a whole topology file.
std::vector<MeasuredPoint> read_measurement(const std::string& file, const gears::GearGeometry& g);

/// Points of measured traces (profile and helix traces per flank, grinding/topology_csv.hpp) on the gear, in file
/// order per flank, row = col = 0; the same checks as measured_points (a point off the flank names its line).
std::vector<MeasuredPoint> trace_points(const std::vector<grinding::FlankTopology>& traces, const gears::GearGeometry& g,
                                        const std::string& source);

/// The same for a whole traces CSV file.
std::vector<MeasuredPoint> read_traces_measurement(const std::string& file, const gears::GearGeometry& g);

} // namespace geartopo::measurement
