// geartopo — one entry for every measurement file a command reads: topology CSV, traces CSV, point cloud or
// Klingelnberg export, told apart by their content (docs/measurement-formats.md), as measured points on the gear or,
// for the ISO 1328-1 evaluator, as traces.
// Units: mm, µm (deviation along the flank normal, plus material positive).
#pragma once

#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/gears/involute_helicoid.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/measurement/measured_points.hpp"

#include <optional>
#include <string>
#include <vector>

namespace geartopo::measurement {

/// Points of a point cloud file (x_mm,y_mm,z_mm in the workpiece frame): each projected onto its flank on the exact
/// helicoid; its deviation is the signed normal distance (plus material). Points farther than max_offset_mm from
/// any flank, or off the active flank, are errors naming the line.
std::vector<MeasuredPoint> read_point_cloud_measurement(const std::string& file, const gears::InvoluteHelicoid& flanks,
                                                        double max_offset_mm = 0.5);

/// What a reader left out of the points it returns (an export's undefined values and points off the active flank):
/// counted so that every count printed about a measurement adds up (docs/measurement-formats.md, "Counts").
struct ReadCounts {
  std::size_t undefined_values = 0;  ///< the export's undefined value −2147483.648: no point
  std::size_t off_flank_points = 0;  ///< an export's points off the active flank (other formats refuse them)
};

/// Topology CSV, traces CSV, point cloud or Klingelnberg export (read with `mka`), told apart by their content, with
/// the deviations referred to the set-up's design (refer_to_design). What a file without a design column is measured
/// from is `against`: as_file, the bare involute, undeclared (MeasuredPoint::reference_declared false); design, the
/// scene's drawing; involute, declared. `against` other than as_file for a file with a design column is an InputError
/// naming its header (the file says it already).
/// Findings that are not errors (blocks a reader skipped, undefined points) go to `warnings` when given; what was left
/// out, counted, to `counts` when given.
std::vector<MeasuredPoint> read_any_measurement(const std::string& file, const grinding::GrindingSetup& setup,
                                                std::vector<std::string>* warnings = nullptr,
                                                const KlingelnbergOptions& mka = {}, ReadCounts* counts = nullptr,
                                                MeasuredAgainst against = MeasuredAgainst::as_file);

/// Points read from a file without a design column (their design_um 0), told what they are measured from: design gives
/// each the set-up's design there, so that refer_to_design keeps its deviation; every point's reference_declared is
/// `against` != as_file.
void declare_reference(std::vector<MeasuredPoint>& points, MeasuredAgainst against, const gears::FlankDesign& design);

/// Measured traces for the ISO 1328-1 evaluator (`geartopo evaluate --traces`).
struct MeasuredTraces {
  std::vector<grinding::FlankTopology> flanks;
  bool klingelnberg = false;         ///< read from a Klingelnberg export (else a traces CSV)
  std::vector<std::string> warnings; ///< the export reader's findings that are not errors
  /// The export as read, when it is one: its pitch tables and curves for what the machine evaluated itself
  /// (workbench::compare_machine_pitch, compare_machine_flank_values), without reading the file again.
  std::optional<KlingelnbergFile> export_file;
};

/// A traces CSV (grinding/topology_csv.hpp) or a Klingelnberg export (klingelnberg_traces, read with `mka`), told
/// apart by their content, with the deviations referred to the set-up's design (refer_to_design).
/// What a file without a design column is measured from is `against`, as for read_any_measurement: design gives each
/// point the set-up's design, so that its deviation is kept as the deviation from the drawing; `against` other than
/// as_file for a file with a design column is an InputError naming its header.
MeasuredTraces read_any_traces(const std::string& file, const grinding::GrindingSetup& setup,
                               const KlingelnbergOptions& mka = {}, MeasuredAgainst against = MeasuredAgainst::as_file);

} // namespace geartopo::measurement
