// geartopo — a ground flank as a triangle mesh: vertices on the actual surface (nominal point + deviation along the
// normal, mm), the deviation in µm as the vertex property "deviation_um". Built from the dense grid when there is
// one, else from the topological grid.
#pragma once

#include "geartopo/gears/involute_helicoid.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/surfaces/triangle_mesh.hpp"

namespace geartopo::grinding {

surfaces::TriangleMesh flank_mesh(const gears::InvoluteHelicoid& flanks, const FlankTopology& ft);

} // namespace geartopo::grinding
