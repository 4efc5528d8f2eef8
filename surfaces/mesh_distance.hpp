// geartopo — closest point and signed distance from a point to a triangle mesh (CGAL AABB tree inside).
//
// CGAL stays in mesh_distance.cpp (pimpl): including this header costs Eigen only. Units: mm.
//
// Sign rule (docs/point-clouds.md): the signed distance is positive outside the material, i.e. on the side the face
// normals point to (faces counter-clockwise seen from outside, TriangleMesh convention). It is the sign of
// (P − C)·N, C the closest point on the mesh and N the angle-weighted pseudo-normal of the feature C lies on
// (Bærentzen & Aanæs, IEEE TVCG 11(3), 2005):
//   - C inside a face:   N = the face normal;
//   - C on an edge:      N = the sum of the unit normals of the faces sharing the edge;
//   - C on a vertex:     N = Σ α_f n_f over the faces around the vertex, α_f the face's angle at that vertex.
// C counts as lying on an edge / vertex when its barycentric coordinates are within 1e-9 of it (ties go to the edge
// or vertex, which is the side that is always safe). For a closed, consistently oriented 2-manifold this sign is exact
// everywhere; for an open mesh (a flank patch) it is exact for every point whose closest point is not on the
// boundary, and near the boundary it reports the side of the nearest face(s).
#pragma once

#include "surfaces/triangle_mesh.hpp"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace geartopo::surfaces {

/// Result of one MeshDistance query. All positions in the mesh's frame (mm).
struct MeshQuery {
  Eigen::Vector3d closest = Eigen::Vector3d::Zero(); ///< closest point C on the mesh
  Eigen::Index face = -1;            ///< index of the face (column of TriangleMesh::faces) C lies on
  int label = -1;                    ///< the face's label, −1 when the mesh was built without labels
  double distance_mm = 0.0;          ///< |P − C| ≥ 0
  double signed_distance_mm = 0.0;   ///< ±|P − C|, positive outside the material (see the sign rule above)
};

/// Distance queries against a fixed triangle mesh. Build once (O(F log F); ~0.1 s for 2e5 faces), then query: a few
/// µs for points near the surface; the cost grows with the distance from the mesh (a point at the centre of a closed
/// sphere visits most of the tree).
///
/// Thread safety: the constructor builds the AABB tree and its distance-acceleration KD-tree eagerly, so `query`
/// only reads shared state; any number of threads may call `query` concurrently on the same object.
///
/// Faces of zero area are left out of the tree (they cannot be the unique closest feature and have no normal).
class MeshDistance {
public:
  /// `labels` is empty or holds one integer per face (e.g. a flank id), returned with each query.
  /// Throws std::invalid_argument when the mesh has no face of non-zero area, a face index is out of range,
  /// a vertex is not finite, or labels.size() is neither 0 nor the face count.
  explicit MeshDistance(const TriangleMesh& mesh, std::vector<int> labels = {});
  ~MeshDistance();
  MeshDistance(MeshDistance&&) noexcept;
  MeshDistance& operator=(MeshDistance&&) noexcept;
  MeshDistance(const MeshDistance&) = delete;
  MeshDistance& operator=(const MeshDistance&) = delete;

  /// Closest point, face, label, unsigned and signed distance of `point` (mm). Throws std::invalid_argument for a
  /// non-finite point.
  MeshQuery query(const Eigen::Vector3d& point) const;

  /// Signed distance only (mm, positive outside).
  double signed_distance(const Eigen::Vector3d& point) const { return query(point).signed_distance_mm; }

  Eigen::Index face_count() const;   ///< faces of the input mesh (including degenerate ones)
  Eigen::Index vertex_count() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace geartopo::surfaces
