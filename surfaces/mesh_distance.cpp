// The only CGAL translation unit of geartopo_surfaces: an AABB tree of the mesh's triangles finds the closest face;
// the closest point on that face, its feature (face / edge / vertex) and the pseudo-normal sign are computed here in
// plain double arithmetic (Ericson, Real-Time Collision Detection §5.1.5; Bærentzen & Aanæs 2005).
#include "surfaces/mesh_distance.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace geartopo::surfaces {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

/// A closest point on a triangle with its barycentric coordinates (for vertices a, b, c).
struct TrianglePoint {
  Eigen::Vector3d point;
  Eigen::Vector3d bary;
};

// Ericson's region test: exact choice of the Voronoi region of p among the triangle's vertices, edges and interior.
TrianglePoint closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                  const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, {1, 0, 0}};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, {0, 1, 0}};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, {1 - v, v, 0}};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, {0, 0, 1}};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, {1 - w, 0, w}};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), {0, 1 - w, w}};
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {a + v * ab + w * ac, {1 - v - w, v, w}};
}

constexpr double kFeatureTolerance = 1e-9; // barycentric coordinate below which C counts as on the edge / vertex

} // namespace

struct MeshDistance::Impl {
  Eigen::Matrix3Xd vertices;
  Eigen::Matrix3Xi faces;
  std::vector<int> labels;
  Eigen::Matrix3Xd face_normals;   // 3×F unit normals (zero for degenerate faces)
  Eigen::Matrix3Xd vertex_normals; // 3×V angle-weighted pseudo-normals
  Eigen::Matrix3Xd edge_normals;   // 3×3F: column 3f+k for edge k (vertex k → vertex k+1) of face f
  std::vector<Triangle> triangles; // non-degenerate faces only, in the tree
  std::vector<Eigen::Index> face_of_triangle;
  Tree tree;
};

MeshDistance::MeshDistance(const TriangleMesh& mesh, std::vector<int> labels) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  const Eigen::Index nv = mesh.vertices.cols(), nf = mesh.faces.cols();
  if (nf == 0 || nv == 0) throw std::invalid_argument("MeshDistance: the mesh is empty");
  if (!labels.empty() && static_cast<Eigen::Index>(labels.size()) != nf)
    throw std::invalid_argument("MeshDistance: " + std::to_string(labels.size()) + " labels for " +
                                std::to_string(nf) + " faces");
  if (!mesh.vertices.allFinite()) throw std::invalid_argument("MeshDistance: a vertex is not finite");
  if (mesh.faces.minCoeff() < 0 || mesh.faces.maxCoeff() >= nv)
    throw std::invalid_argument("MeshDistance: a face refers to a vertex outside 0.." + std::to_string(nv - 1));

  m.vertices = mesh.vertices;
  m.faces = mesh.faces;
  m.labels = std::move(labels);
  m.face_normals.setZero(3, nf);
  m.vertex_normals.setZero(3, nv);
  m.edge_normals.setZero(3, 3 * nf);
  m.triangles.reserve(static_cast<size_t>(nf));
  m.face_of_triangle.reserve(static_cast<size_t>(nf));

  // Face normals, angle-weighted vertex normals, and the list of (edge key, face edge) pairs.
  std::vector<std::pair<std::uint64_t, Eigen::Index>> edges;
  edges.reserve(static_cast<size_t>(3 * nf));
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d p[3] = {m.vertices.col(m.faces(0, f)), m.vertices.col(m.faces(1, f)),
                                  m.vertices.col(m.faces(2, f))};
    const Eigen::Vector3d cross = (p[1] - p[0]).cross(p[2] - p[0]);
    const double longest2 =
        std::max({(p[1] - p[0]).squaredNorm(), (p[2] - p[1]).squaredNorm(), (p[0] - p[2]).squaredNorm()});
    if (!(cross.norm() > 1e-14 * longest2)) continue; // zero area: no normal, not in the tree
    const Eigen::Vector3d n = cross.normalized();
    m.face_normals.col(f) = n;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      m.vertex_normals.col(m.faces(k, f)) += angle * n;
      const auto a = static_cast<std::uint64_t>(m.faces(k, f)), b = static_cast<std::uint64_t>(m.faces((k + 1) % 3, f));
      edges.emplace_back(std::min(a, b) * static_cast<std::uint64_t>(nv) + std::max(a, b), 3 * f + k);
    }
    m.triangles.emplace_back(Point(p[0].x(), p[0].y(), p[0].z()), Point(p[1].x(), p[1].y(), p[1].z()),
                             Point(p[2].x(), p[2].y(), p[2].z()));
    m.face_of_triangle.push_back(f);
  }
  if (m.triangles.empty()) throw std::invalid_argument("MeshDistance: every face of the mesh has zero area");

  // Edge pseudo-normal: the sum of the unit normals of all faces sharing the (undirected) edge.
  std::sort(edges.begin(), edges.end());
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (; j < edges.size() && edges[j].first == edges[i].first; ++j) sum += m.face_normals.col(edges[j].second / 3);
    for (size_t k = i; k < j; ++k) m.edge_normals.col(edges[k].second) = sum;
    i = j;
  }

  // Build both trees now so that const queries never trigger a lazy build (thread safety).
  m.tree.insert(m.triangles.cbegin(), m.triangles.cend());
  m.tree.build();
  m.tree.accelerate_distance_queries();
}

MeshDistance::~MeshDistance() = default;
MeshDistance::MeshDistance(MeshDistance&&) noexcept = default;
MeshDistance& MeshDistance::operator=(MeshDistance&&) noexcept = default;

Eigen::Index MeshDistance::face_count() const { return impl_->faces.cols(); }
Eigen::Index MeshDistance::vertex_count() const { return impl_->vertices.cols(); }

MeshQuery MeshDistance::query(const Eigen::Vector3d& point) const {
  if (!point.allFinite()) throw std::invalid_argument("MeshDistance::query: the point is not finite");
  const Impl& m = *impl_;
  const auto hit = m.tree.closest_point_and_primitive(Point(point.x(), point.y(), point.z()));
  const Eigen::Index f = m.face_of_triangle[static_cast<size_t>(hit.second - m.triangles.cbegin())];

  const TrianglePoint tp = closest_on_triangle(point, m.vertices.col(m.faces(0, f)), m.vertices.col(m.faces(1, f)),
                                               m.vertices.col(m.faces(2, f)));
  // The feature C lies on: count the barycentric coordinates that vanish.
  int zeros = 0, zero_at = -1, nonzero_at = -1;
  for (int k = 0; k < 3; ++k) {
    if (tp.bary[k] <= kFeatureTolerance) {
      ++zeros;
      zero_at = k;
    } else {
      nonzero_at = k;
    }
  }
  Eigen::Vector3d normal;
  if (zeros == 0)
    normal = m.face_normals.col(f);
  else if (zeros == 1)
    normal = m.edge_normals.col(3 * f + (zero_at + 1) % 3); // edge opposite the vanishing vertex
  else
    normal = m.vertex_normals.col(m.faces(nonzero_at, f));

  MeshQuery q;
  q.closest = tp.point;
  q.face = f;
  q.label = m.labels.empty() ? -1 : m.labels[static_cast<size_t>(f)];
  const Eigen::Vector3d d = point - tp.point;
  q.distance_mm = d.norm();
  q.signed_distance_mm = d.dot(normal) < 0.0 ? -q.distance_mm : q.distance_mm;
  return q;
}

} // namespace geartopo::surfaces
