// geartopo — the exact involute helicoid flanks of every tooth, in the workpiece frame.
//
// Workpiece frame w: origin on the gear axis in the datum face, z along the axis into the gear (0 ≤ z ≤ b),
// x through the centre of tooth 1 at the datum face. Teeth are numbered 1..z with increasing polar angle θ
// about +z, which is clockwise seen from the datum face (docs/conventions.md).
// Flank coordinates: roll length ξ = √(r² − r_b²) (mm, transverse) and axial position z (mm).
// Units: mm, rad. The surface normal points out of the material (into the tooth space).
#pragma once

#include "geartopo/core/flank.hpp"
#include "geartopo/gears/gear_geometry.hpp"

#include <Eigen/Core>

#include <optional>

namespace geartopo::gears {

/// A point on a flank with its first-order geometry, all in the workpiece frame w.
struct FlankPoint {
  Eigen::Vector3d p;    ///< wP, position (mm)
  Eigen::Vector3d n;    ///< unit normal, out of the material
  Eigen::Vector3d d_xi; ///< ∂P/∂ξ (dimensionless; |∂P/∂ξ| = ξ/r_b, lies in the transverse plane)
  Eigen::Vector3d d_z;  ///< ∂P/∂z at fixed ξ (dimensionless; follows the helix)
};

/// Where a point near a flank projects onto it.
struct FlankLocation {
  int tooth = 0;                ///< 1..z
  Flank flank = Flank::Left;
  double roll_length_mm = 0.0;  ///< ξ of the foot point
  double diameter_mm = 0.0;     ///< 2√(r_b² + ξ²)
  double z_mm = 0.0;            ///< axial position of the foot point
  double normal_distance_mm = 0.0; ///< (P − foot)·n: positive outside the material ("plus material")
  Eigen::Vector3d foot;         ///< wP of the foot point
  Eigen::Vector3d normal;       ///< flank normal at the foot point
};

class InvoluteHelicoid {
public:
  explicit InvoluteHelicoid(const GearGeometry& geometry) : g_(geometry) {}

  const GearGeometry& geometry() const { return g_; }

  /// Polar angle (rad) of tooth `tooth`'s centre line at axial position z: 2π(tooth−1)/z + (2 tan β / d)·z.
  double tooth_centre_angle(int tooth, double z_mm) const;

  /// Flank point at roll length ξ ≥ 0 and axial position z (z may lie outside [0, b]: the surface continues).
  FlankPoint at(int tooth, Flank flank, double roll_length_mm, double z_mm) const;
  /// Same at a diameter d_y ≥ d_b.
  FlankPoint at_diameter(int tooth, Flank flank, double diameter_mm, double z_mm) const;

  /// Foot point on the nearest flank of the nearest tooth (orthogonal projection, Gauss–Newton on (ξ, z)).
  /// nullopt when the point is inside the base cylinder or the projection does not converge.
  std::optional<FlankLocation> locate(const Eigen::Vector3d& wP) const;
  /// Same, on a given tooth and flank.
  std::optional<FlankLocation> locate_on(const Eigen::Vector3d& wP, int tooth, Flank flank) const;

private:
  GearGeometry g_; // a copy: the surface must not outlive a temporary geometry
};

} // namespace geartopo::gears
