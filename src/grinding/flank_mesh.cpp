#include "geartopo/grinding/flank_mesh.hpp"
#include "geartopo/core/units.hpp"

#include <stdexcept>

namespace geartopo::grinding {

surfaces::TriangleMesh flank_mesh(const gears::InvoluteHelicoid& flanks, const FlankTopology& ft) {
  const auto& pts = ft.dense.empty() ? ft.grid : ft.dense;
  if (pts.empty()) throw std::invalid_argument("flank_mesh: no grid");
  const int rows = pts.back().row, cols = pts.back().col;
  surfaces::TriangleMesh m;
  m.vertices.resize(3, rows * cols);
  m.vertex_values.resize(rows * cols);
  m.value_name = "deviation_um";
  for (const auto& p : pts) {
    const int i = (p.row - 1) * cols + (p.col - 1);
    const auto fp = flanks.at(ft.tooth, ft.flank, p.roll_length_mm, p.z_mm);
    m.vertices.col(i) = fp.p + units::mm_from_um(p.deviation_um) * fp.n;
    m.vertex_values(i) = p.deviation_um;
  }
  // Orientation: (∂P/∂ξ × ∂P/∂z)·n has the sign of the flank side; order the triangles so their normals point out
  // of the material like n.
  const auto fp = flanks.at(ft.tooth, ft.flank, pts.front().roll_length_mm + 1.0, pts.front().z_mm);
  const bool flip = fp.d_xi.cross(fp.d_z).dot(fp.n) < 0.0;
  m.faces.resize(3, 2 * (rows - 1) * (cols - 1));
  int f = 0;
  for (int r = 0; r + 1 < rows; ++r)
    for (int c = 0; c + 1 < cols; ++c) {
      const int a = r * cols + c, b = (r + 1) * cols + c, d = r * cols + c + 1, e = (r + 1) * cols + c + 1;
      if (!flip) {
        m.faces.col(f++) << a, b, e;
        m.faces.col(f++) << a, e, d;
      } else {
        m.faces.col(f++) << a, e, b;
        m.faces.col(f++) << a, d, e;
      }
    }
  return m;
}

} // namespace geartopo::grinding
