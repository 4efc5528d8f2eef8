// geartopo — a closed triangle mesh of the nominal gear: every tooth with both involute flanks, tip, root and the
// two end faces, swept helically from the datum face (z = 0) to z = b. Units: mm.
//
// The involute flanks are exact at the vertices (InvoluteHelicoid). Between the root form circle and the root circle
// the mesh draws a smooth blend, not the real generated fillet: it is for viewing, not for measuring.
#pragma once

#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/surfaces/triangle_mesh.hpp"

namespace geartopo::surfaces {

struct GearMeshOptions {
  int flank_points = 16; ///< profile points per flank, root form to tip (≥ 2)
  int tip_points = 4;    ///< points on the tip land, ends included (≥ 2)
  int fillet_points = 4; ///< points from root form circle to root circle (≥ 2)
  int root_points = 5;   ///< points on the root arc of each space, ends included (≥ 2)
  int slices = 31;       ///< transverse sections from z = 0 to z = b (≥ 2)
};

/// Number of points of one transverse section of the whole gear.
int section_point_count(const gears::GearGeometry& g, const GearMeshOptions& o);

TriangleMesh gear_mesh(const gears::GearGeometry& g, const GearMeshOptions& options = {});

} // namespace geartopo::surfaces
