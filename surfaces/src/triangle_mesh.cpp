#include "geartopo/surfaces/triangle_mesh.hpp"

#include <Eigen/Geometry>

namespace geartopo::surfaces {

double signed_volume(const TriangleMesh& mesh) {
  double v6 = 0.0; // Σ a·(b × c) = 6 × volume of the tetrahedra on the origin
  for (Eigen::Index f = 0; f < mesh.faces.cols(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.col(mesh.faces(0, f)), b = mesh.vertices.col(mesh.faces(1, f)),
                          c = mesh.vertices.col(mesh.faces(2, f));
    v6 += a.dot(b.cross(c));
  }
  return v6 / 6.0;
}

} // namespace geartopo::surfaces
