// geartopo — measured point clouds of gear flanks: a strict CSV reader and the assignment of each point to the exact
// nominal flank it lies on (tooth, flank, diameter, z, signed normal distance). Format and rules: docs/point-clouds.md.
//
// Points are in the workpiece frame w (docs/conventions.md): origin on the axis in the datum face, z into the gear.
// Units: mm. Distances are signed "plus material positive": positive outside the material, along the flank normal.
#pragma once

#include "geartopo/core/flank.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace geartopo::gears {
class InvoluteHelicoid;
}

namespace geartopo::surfaces {

/// Header of a point-cloud CSV file; `,id` may follow as a fourth column.
inline constexpr const char* kPointCloudHeader = "x_mm,y_mm,z_mm";

/// Two points at most this far apart (Euclidean, mm) are duplicates.
inline constexpr double kDuplicatePointTolerance_mm = 1e-9;

/// One measured point.
struct CloudPoint {
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero(); ///< wP (mm)
  std::int64_t line = 0; ///< 1-based line of the file it was read from (0 for points made in code)
  std::int64_t id = -1;  ///< the `id` column (a whole number ≥ 0, unique in the file), −1 when the file has none
};

/// Reads a point cloud. Strict: the first line that is neither blank nor a comment ('#' after optional blanks) must
/// be the header `x_mm,y_mm,z_mm` or `x_mm,y_mm,z_mm,id`; every further such line is one point with exactly as many
/// fields. Blanks around fields, a trailing '\r' and a UTF-8 byte-order mark are ignored.
/// Throws std::runtime_error "source:line:column: field: message" for a missing or wrong header, a wrong field count,
/// a field that is not a number, NaN or infinity, an id that is not a whole number ≥ 0 or repeats, a point that
/// duplicates an earlier one (|P − Q| ≤ kDuplicatePointTolerance_mm), or a file without points.
/// Repeats (points, ids) are looked for once the whole input has been parsed, so a syntax error anywhere is reported
/// before them; of several repeats the one on the earliest line is reported, naming the line it repeats.
/// Nothing is returned on error. The input is read line by line: memory is linear in the number of points
/// (about 70 bytes per point at the peak), time about 0.5 µs per row.
std::vector<CloudPoint> read_point_cloud(std::istream& in, const std::string& source);
/// Same from a file; `source` in messages is the path. Throws std::runtime_error when the file cannot be opened.
std::vector<CloudPoint> read_point_cloud(const std::filesystem::path& file);

/// Whether the input's first line that is neither blank nor a comment starts with the column x_mm, by the same rules
/// as read_point_cloud (BOM, '\r', blanks): how a reader of "any measurement" tells a cloud from a topology file.
/// Reads up to that line.
bool starts_like_point_cloud(std::istream& in);

/// Where one measured point lies relative to the exact nominal flanks.
struct FlankSample {
  int tooth = 0;                   ///< 1..z
  geartopo::Flank flank = geartopo::Flank::Left;
  double roll_length_mm = 0.0;     ///< ξ of the foot point on the nominal flank
  double diameter_mm = 0.0;        ///< d_y of the foot point
  double z_mm = 0.0;               ///< axial position of the foot point
  double normal_distance_mm = 0.0; ///< (P − foot)·n: positive outside the material ("plus material")
  std::int64_t line = 0;           ///< from the CloudPoint
  std::int64_t id = -1;            ///< from the CloudPoint
};

/// Margins by which a foot point may lie outside the evaluated flank, for assign_to_flanks (mm).
struct FlankRangeTolerance {
  double diameter_mm = 0.01; ///< on d_Ff ≤ d_y ≤ d_a
  double z_mm = 0.01;        ///< on 0 ≤ z ≤ b
};

/// Projects every point onto the nearest exact flank (gears::InvoluteHelicoid::locate, an orthogonal projection).
/// Throws std::runtime_error "source:line:1: point: message" naming the first offending point's line when
///   - locate refuses it (inside the base cylinder, or no convergence),
///   - |normal distance| > max_offset_mm ("off the flank"),
///   - its foot point lies outside [d_Ff, d_a] or [0, b] by more than the tolerance.
/// Throws std::invalid_argument unless max_offset_mm is finite and > 0. The result has one sample per point, in order.
std::vector<FlankSample> assign_to_flanks(const std::vector<CloudPoint>& points, const gears::InvoluteHelicoid& flanks,
                                          double max_offset_mm, const std::string& source,
                                          const FlankRangeTolerance& tolerance = {});

} // namespace geartopo::surfaces
