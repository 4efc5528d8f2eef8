// Mesh distance (CGAL AABB tree, pseudo-normal sign), the point-cloud reader and the assignment of measured points to
// the exact nominal flanks. Tolerances are physical: exact answers for planar meshes, the chord (sag) bound of the
// triangulation for curved ones.
#include "surfaces/gear_mesh.hpp"
#include "surfaces/mesh_distance.hpp"
#include "surfaces/point_cloud.hpp"

#include "gears/involute_helicoid.hpp"
#include "../gears/gear_fixtures.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <thread>
#include <tuple>

using namespace geartopo;
using gears::Flank;

namespace {

// ---------------------------------------------------------------------------------------------------------------
// Meshes with known distances

/// The cube [0, 1]³, two triangles per side, counter-clockwise from outside. Label = side: 0 −x, 1 +x, 2 −y, 3 +y,
/// 4 −z, 5 +z.
surfaces::TriangleMesh unit_cube(std::vector<int>* labels) {
  surfaces::TriangleMesh m;
  m.vertices.resize(3, 8);
  for (int i = 0; i < 8; ++i) m.vertices.col(i) = Eigen::Vector3d(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  // Each side as a quad a, b, c, d counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  m.faces.resize(3, 12);
  labels->clear();
  for (int s = 0; s < 6; ++s) {
    const auto& q = quads[s];
    m.faces.col(2 * s) << q[0], q[1], q[2];
    m.faces.col(2 * s + 1) << q[0], q[2], q[3];
    labels->push_back(s);
    labels->push_back(s);
  }
  return m;
}

/// Exact signed distance to the box [0, 1]³, positive outside.
double cube_sdf(const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = (p - Eigen::Vector3d::Constant(0.5)).cwiseAbs() - Eigen::Vector3d::Constant(0.5);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// Icosphere of radius r: an icosahedron subdivided `levels` times, vertices pushed onto the sphere.
surfaces::TriangleMesh icosphere(double r, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& p : v) p.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      if (auto it = mid.find(key); it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Eigen::Vector3i> g;
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      g.insert(g.end(), {{tri[0], a, c}, {tri[1], b, a}, {tri[2], c, b}, {a, b, c}});
    }
    f = std::move(g);
  }
  surfaces::TriangleMesh m;
  m.vertices.resize(3, static_cast<Eigen::Index>(v.size()));
  for (size_t i = 0; i < v.size(); ++i) m.vertices.col(static_cast<Eigen::Index>(i)) = r * v[i];
  m.faces.resize(3, static_cast<Eigen::Index>(f.size()));
  for (size_t i = 0; i < f.size(); ++i) m.faces.col(static_cast<Eigen::Index>(i)) = f[i];
  return m;
}

// ---------------------------------------------------------------------------------------------------------------
// MeshDistance on the cube and the sphere

TEST(MeshDistance, CubeSignedDistancesAreExactInsideOutsideAndAtEdgesAndCorners) {
  std::vector<int> labels;
  const surfaces::TriangleMesh cube = unit_cube(&labels);
  ASSERT_GT(surfaces::signed_volume(cube), 0.0); // outward faces
  const surfaces::MeshDistance md(cube, labels);
  EXPECT_EQ(md.face_count(), 12);

  struct Case {
    Eigen::Vector3d p;
    double expected;
    int label; // −1: any
  };
  const Case cases[] = {
      {{0.5, 0.5, 0.5}, -0.5, -1},                          // centre: a six-way tie, inside
      {{0.5, 0.5, 0.2}, -0.2, 4},                           // inside, nearest the −z side
      {{0.5, 0.5, 1.3}, 0.3, 5},                            // outside above +z
      {{0.9, 0.9, 0.9}, -0.1, -1},                          // inside, three-way tie at a corner
      {{0.95, 0.97, 0.5}, -0.03, 3},                        // inside, close to the +x/+y edge
      {{1.2, 1.2, 0.5}, 0.2 * std::sqrt(2.0), -1},          // outside, closest point on an edge
      {{1.1, 1.2, 1.3}, std::sqrt(0.01 + 0.04 + 0.09), -1}, // outside, closest point a corner
      {{-0.4, 0.5, 0.5}, 0.4, 0},                           // outside beyond −x
      {{0.3, 0.6, 0.0}, 0.0, 4},                            // on the surface
  };
  for (const auto& c : cases) {
    const surfaces::MeshQuery q = md.query(c.p);
    EXPECT_NEAR(q.signed_distance_mm, c.expected, 1e-12) << c.p.transpose();
    EXPECT_NEAR(q.distance_mm, std::abs(c.expected), 1e-12);
    EXPECT_NEAR((q.closest - c.p).norm(), q.distance_mm, 1e-12);
    if (c.label >= 0) {
      EXPECT_EQ(q.label, c.label) << c.p.transpose();
    }
    EXPECT_EQ(q.label, labels[static_cast<size_t>(q.face)]);
  }

  // Random points, including many whose closest feature is an edge or a corner.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.6, 1.6);
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    ASSERT_NEAR(md.signed_distance(p), cube_sdf(p), 1e-12) << p.transpose();
  }
}

// Sharp edges (dihedral 70.5°) and corners: the normal cone of an edge spans 109.5°, so the face normal alone gives
// the wrong sign for part of the edge region; the pseudo-normal must not. Reference for a convex polytope: the point
// is outside iff it is outside one of the face planes, inside sd = max plane distance, outside sd ≥ max plane distance.
// The inverted mesh (every face flipped) is the complement: material outside, all signs reversed (concave edges).
TEST(MeshDistance, TetrahedronSignIsRightInEdgeAndCornerRegionsForBothOrientations) {
  surfaces::TriangleMesh tet;
  tet.vertices.resize(3, 4);
  tet.vertices << 1, 1, -1, -1, //
      1, -1, 1, -1,             //
      1, -1, -1, 1;
  tet.faces.resize(3, 4);
  tet.faces << 0, 0, 0, 1, //
      1, 2, 3, 3,          //
      2, 3, 1, 2;
  ASSERT_NEAR(surfaces::signed_volume(tet), 8.0 / 3.0, 1e-12); // every face outward
  surfaces::TriangleMesh inverted = tet;
  inverted.faces.row(1).swap(inverted.faces.row(2));
  const surfaces::MeshDistance md(tet), md_inverted(inverted);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  int outside = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    double plane = -1e300;
    for (Eigen::Index f = 0; f < 4; ++f) {
      const Eigen::Vector3d a = tet.vertices.col(tet.faces(0, f)), b = tet.vertices.col(tet.faces(1, f)),
                            c = tet.vertices.col(tet.faces(2, f));
      plane = std::max(plane, (p - a).dot((b - a).cross(c - a).normalized()));
    }
    const double sd = md.signed_distance(p);
    if (plane > 1e-12) {
      ++outside;
      ASSERT_GE(sd, plane - 1e-12) << p.transpose();
    } else if (plane < -1e-12) {
      ASSERT_NEAR(sd, plane, 1e-12) << p.transpose();
    }
    ASSERT_NEAR(md_inverted.signed_distance(p), -sd, 1e-12) << p.transpose();
  }
  EXPECT_GT(outside, 15000);
}

TEST(MeshDistance, RejectsEmptyAndInconsistentMeshes) {
  EXPECT_THROW(surfaces::MeshDistance(surfaces::TriangleMesh{}), std::invalid_argument);
  std::vector<int> labels;
  const surfaces::TriangleMesh cube = unit_cube(&labels);
  labels.pop_back();
  EXPECT_THROW(surfaces::MeshDistance(cube, labels), std::invalid_argument);
  surfaces::TriangleMesh bad = cube;
  bad.faces(1, 3) = 8;
  EXPECT_THROW(surfaces::MeshDistance{bad}, std::invalid_argument);
  surfaces::TriangleMesh flat = cube;
  flat.faces.row(1) = flat.faces.row(0); // every face degenerate
  EXPECT_THROW(surfaces::MeshDistance{flat}, std::invalid_argument);
  const surfaces::MeshDistance md(cube);
  EXPECT_EQ(md.query({2, 2, 2}).label, -1);
  EXPECT_THROW(md.query({std::nan(""), 0, 0}), std::invalid_argument);
}

// The icosphere lies between the ball of its inradius r_in (the nearest face plane) and the sphere R through its
// vertices. Signed distance is monotone under inclusion, so for |P| = ρ: ρ − R ≤ sd ≤ ρ − r_in. The gap R − r_in is
// the chord error: for 4 subdivisions (5120 faces) about R (1 − cos 2.6°) ≈ 1e-3 R.
TEST(MeshDistance, SphereSignedDistanceIsWithinTheChordErrorOfTheExactOne) {
  const double R = 10.0;
  const surfaces::TriangleMesh sphere = icosphere(R, 4);
  ASSERT_EQ(sphere.faces.cols(), 5120);
  ASSERT_GT(surfaces::signed_volume(sphere), 0.0);
  double r_in = R;
  for (Eigen::Index f = 0; f < sphere.faces.cols(); ++f) {
    const Eigen::Vector3d a = sphere.vertices.col(sphere.faces(0, f)), b = sphere.vertices.col(sphere.faces(1, f)),
                          c = sphere.vertices.col(sphere.faces(2, f));
    r_in = std::min(r_in, std::abs(a.dot((b - a).cross(c - a).normalized())));
  }
  const double chord = R - r_in;
  EXPECT_LT(chord, 1.5e-3 * R);
  EXPECT_GT(chord, 0.5e-3 * R);

  std::vector<int> labels(static_cast<size_t>(sphere.faces.cols()));
  for (size_t i = 0; i < labels.size(); ++i) labels[i] = static_cast<int>(i % 7);
  const surfaces::MeshDistance md(sphere, labels);
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> radius(0.1, 2.0 * R);
  int inside = 0, outside = 0;
  for (int i = 0; i < 5000; ++i) {
    const Eigen::Vector3d dir = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const double rho = radius(rng);
    const surfaces::MeshQuery q = md.query(rho * dir);
    ASSERT_GE(q.signed_distance_mm, rho - R - 1e-12);
    ASSERT_LE(q.signed_distance_mm, rho - r_in + 1e-12);
    ASSERT_EQ(q.label, static_cast<int>(q.face % 7));
    (q.signed_distance_mm < 0 ? inside : outside)++;
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
}

TEST(MeshDistance, ConcurrentQueriesGiveTheSameResultsAsSerialOnes) {
  const surfaces::MeshDistance md(icosphere(10.0, 4));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-15.0, 15.0);
  std::vector<Eigen::Vector3d> pts(10000);
  for (auto& p : pts) p = {u(rng), u(rng), u(rng)};

  std::vector<surfaces::MeshQuery> serial(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) serial[i] = md.query(pts[i]);

  // Two threads each query every point (interleaved order), at the same time, on the same object.
  std::vector<surfaces::MeshQuery> a(pts.size()), b(pts.size());
  std::thread ta([&] { for (size_t i = 0; i < pts.size(); ++i) a[i] = md.query(pts[i]); });
  std::thread tb([&] { for (size_t i = pts.size(); i-- > 0;) b[i] = md.query(pts[i]); });
  ta.join();
  tb.join();
  for (size_t i = 0; i < pts.size(); ++i) {
    ASSERT_EQ(a[i].face, serial[i].face);
    ASSERT_EQ(b[i].face, serial[i].face);
    ASSERT_EQ(a[i].signed_distance_mm, serial[i].signed_distance_mm);
    ASSERT_EQ(b[i].signed_distance_mm, serial[i].signed_distance_mm);
    ASSERT_EQ(a[i].closest, serial[i].closest);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// The real gear: m_n 14, z 35, α_n 20°, β 30° right hand, x 0.274, b 150 (tests/gears/gear_fixtures.hpp)

class GearPointTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    geometry_ = new gears::GearGeometry(test::paper_gear());
    flanks_ = new gears::InvoluteHelicoid(*geometry_);
  }
  static void TearDownTestSuite() {
    delete flanks_;
    delete geometry_;
  }
  static double xi_ff() { return geometry_->roll_length_at(geometry_->root_form_diameter_mm()); }
  static double xi_a() { return geometry_->roll_length_at(geometry_->tip_diameter_mm()); }
  static inline gears::GearGeometry* geometry_ = nullptr;
  static inline gears::InvoluteHelicoid* flanks_ = nullptr;
};

/// Appends a grid patch of one flank, ξ0..ξ1 × z0..z1 with (nxi × nz) cells, to `mesh`, labelled `label`.
/// The (ξ, z) parametrisation turns one way on right flanks and the other on left flanks: each triangle's winding is
/// chosen from the exact normal so that the faces point out of the material. Returns whether it had to be flipped.
bool append_flank_patch(surfaces::TriangleMesh& mesh, std::vector<int>& labels, const gears::InvoluteHelicoid& h,
                        int tooth, Flank flank, double xi0, double xi1, int nxi, double z0, double z1, int nz,
                        int label) {
  const Eigen::Index base = mesh.vertices.cols();
  const int cols = nz + 1;
  mesh.vertices.conservativeResize(3, base + (nxi + 1) * cols);
  for (int i = 0; i <= nxi; ++i)
    for (int j = 0; j <= nz; ++j)
      mesh.vertices.col(base + i * cols + j) =
          h.at(tooth, flank, xi0 + (xi1 - xi0) * i / nxi, z0 + (z1 - z0) * j / nz).p;
  const gears::FlankPoint mid = h.at(tooth, flank, 0.5 * (xi0 + xi1), 0.5 * (z0 + z1));
  const Eigen::Vector3d along_xi = mesh.vertices.col(base + cols) - mesh.vertices.col(base);
  const Eigen::Vector3d along_z = mesh.vertices.col(base + 1) - mesh.vertices.col(base);
  const bool flip = along_xi.cross(along_z).dot(mid.n) < 0.0;
  const Eigen::Index f0 = mesh.faces.cols();
  mesh.faces.conservativeResize(3, f0 + 2 * nxi * nz);
  Eigen::Index f = f0;
  for (int i = 0; i < nxi; ++i)
    for (int j = 0; j < nz; ++j) {
      const int a = static_cast<int>(base) + i * cols + j, b = a + cols, c = b + 1, d = a + 1;
      mesh.faces.col(f++) = flip ? Eigen::Vector3i(a, c, b) : Eigen::Vector3i(a, b, c);
      mesh.faces.col(f++) = flip ? Eigen::Vector3i(a, d, c) : Eigen::Vector3i(a, c, d);
      labels.push_back(label);
      labels.push_back(label);
    }
  return flip;
}

// Chord error of the patch. The involute helicoid is developable: its only curvature is across the generating line,
// in the transverse direction e_r, κ = cos β_b / ξ (the involute's curvature 1/ξ, Meusnier with the β_b tilt). Along
// a grid edge the e_r-component of the step is ξΔξ/r_b (ξ edges) or kξΔz (z edges, k = 2 tan β / d), so within a
// triangle it spans at most Δu = ξ_a(Δξ/r_b + kΔz), and the linear interpolant sags below the convex flank by at most
// κ_max Δu²/8. The mesh lies on the material side, so for a point at exact signed distance δ the mesh distance is
// δ + sag, 0 ≤ sag ≤ κ_max Δu²/8 (second-order tilt terms ~ δ (κΔu)² are < 1e-10 mm here).
TEST_F(GearPointTest, AabbSignedDistanceToADenseFlankPatchEqualsTheExactOffsetWithinTheChordError) {
  const gears::GearGeometry& g = *geometry_;
  const double rb = 0.5 * g.base_diameter_mm(), k = std::abs(g.twist_rad_per_mm());
  const double xi0 = xi_ff(), xi1 = xi_a(), z0 = 60.0, z1 = 75.0;
  const int nxi = 440, nz = 150;
  const double dxi = (xi1 - xi0) / nxi, dz = (z1 - z0) / nz;
  const double du = xi1 * (dxi / rb + k * dz);
  const double kappa = std::cos(g.base_helix_angle()) / xi0;
  const double chord = kappa * du * du / 8.0;
  EXPECT_LT(chord, 5e-5) << "grid too coarse for a 0.05 µm chord error";

  surfaces::TriangleMesh patch;
  patch.vertices.resize(3, 0);
  patch.faces.resize(3, 0);
  std::vector<int> labels;
  // Both flanks of tooth space 1: tooth 1's right flank faces tooth 2's left flank.
  const bool flip_right = append_flank_patch(patch, labels, *flanks_, 1, Flank::Right, xi0, xi1, nxi, z0, z1, nz, 11);
  const bool flip_left = append_flank_patch(patch, labels, *flanks_, 2, Flank::Left, xi0, xi1, nxi, z0, z1, nz, 22);
  EXPECT_NE(flip_right, flip_left); // the two orientations really occur
  const surfaces::MeshDistance md(patch, labels);

  std::mt19937 rng(5);
  const double margin = 1.0; // mm from the patch boundary: the closest point is inside the patch
  std::uniform_real_distribution<double> uxi(xi0 + margin, xi1 - margin), uz(z0 + margin, z1 - margin);
  const double deltas[] = {0.002, 0.005, 0.010, 0.020, 0.050};
  double worst = 0.0, least = 1.0;
  for (const auto& [tooth, flank, label] : {std::tuple{1, Flank::Right, 11}, std::tuple{2, Flank::Left, 22}}) {
    for (int i = 0; i < 400; ++i) {
      const gears::FlankPoint fp = flanks_->at(tooth, flank, uxi(rng), uz(rng));
      for (const double delta : deltas)
        for (const double s : {+1.0, -1.0}) {
          const Eigen::Vector3d p = fp.p + s * delta * fp.n;
          const auto exact = flanks_->locate(p);
          ASSERT_TRUE(exact);
          ASSERT_NEAR(exact->normal_distance_mm, s * delta, 1e-10); // the reference itself
          const surfaces::MeshQuery q = md.query(p);
          ASSERT_EQ(q.label, label);
          const double excess = q.signed_distance_mm - s * delta;
          ASSERT_GE(excess, -1e-10) << "δ = " << s * delta;
          ASSERT_LE(excess, chord + 1e-10) << "δ = " << s * delta;
          worst = std::max(worst, excess);
          least = std::min(least, excess);
        }
    }
  }
  RecordProperty("chord_bound_um", std::to_string(chord * 1e3));
  RecordProperty("largest_excess_um", std::to_string(worst * 1e3));
  EXPECT_GT(worst, 0.1 * chord); // the sag is really seen, the bound is not vacuous
}

// On the closed nominal gear mesh (surfaces::gear_mesh), material reads negative and tooth spaces positive.
TEST_F(GearPointTest, ClosedGearMeshIsPlusMaterialPositive) {
  surfaces::GearMeshOptions o;
  o.flank_points = 32;
  o.slices = 61;
  const surfaces::MeshDistance md(surfaces::gear_mesh(*geometry_, o));
  const double b = geometry_->spec().face_width_mm;
  // On the axis, mid face width: the nearest surface is an end face (planar, so exact).
  EXPECT_NEAR(md.signed_distance({0, 0, 40.0}), -40.0, 1e-9);
  EXPECT_NEAR(md.signed_distance({0, 0, b + 3.0}), 3.0, 1e-9);
  // Same chord bound as above with Δξ = (ξ_a − ξ_Ff)/31, Δz = b/60.
  const double rb = 0.5 * geometry_->base_diameter_mm(), k = std::abs(geometry_->twist_rad_per_mm());
  const double du = xi_a() * ((xi_a() - xi_ff()) / (o.flank_points - 1) / rb + k * b / (o.slices - 1));
  const double chord = std::cos(geometry_->base_helix_angle()) / xi_ff() * du * du / 8.0;
  const double d = geometry_->reference_diameter_mm(), z = 75.0, pitch = 2.0 * std::numbers::pi / geometry_->teeth();
  for (int tooth : {1, 9, 35}) {
    const double centre = flanks_->tooth_centre_angle(tooth, z);
    const Eigen::Vector3d in_tooth(0.5 * d * std::cos(centre), 0.5 * d * std::sin(centre), z);
    const double space = centre + 0.5 * pitch;
    const Eigen::Vector3d in_space(0.5 * d * std::cos(space), 0.5 * d * std::sin(space), z);
    const double exact_tooth = flanks_->locate(in_tooth)->normal_distance_mm;
    const double exact_space = flanks_->locate(in_space)->normal_distance_mm;
    EXPECT_LT(exact_tooth, -5.0);
    EXPECT_GT(exact_space, 5.0);
    EXPECT_NEAR(md.signed_distance(in_tooth), exact_tooth, chord + 1e-9) << "tooth " << tooth;
    EXPECT_NEAR(md.signed_distance(in_space), exact_space, chord + 1e-9) << "tooth " << tooth;
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Reader and assignment

std::string g17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// Message of the std::runtime_error that `f` throws, or "" if it throws nothing.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

std::vector<surfaces::CloudPoint> read_text(const std::string& text, const std::string& name = "cloud.csv") {
  std::istringstream in(text);
  return surfaces::read_point_cloud(in, name);
}

#define EXPECT_ERROR(expr, expected)                                                                                   \
  do {                                                                                                                 \
    const std::string msg_ = error_of([&] { (void)(expr); });                                                          \
    EXPECT_NE(msg_.find(expected), std::string::npos)                                                                \
        << "message: '" << msg_ << "'\nexpected: '" << (expected) << "'";                                              \
  } while (0)

TEST(PointCloudReader, ReadsPointsWithCommentsBlankLinesCrLfBomAndIds) {
  const auto pts = read_text("\xEF\xBB\xBF# probe run 7, workpiece frame\r\n\r\n x_mm , y_mm,z_mm\r\n1.5,-2,3e2\r\n"
                             "# a comment between rows\n   \n+4,5.25,-6\n");
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_EQ(pts[0].position_mm, Eigen::Vector3d(1.5, -2, 300));
  EXPECT_EQ(pts[0].line, 4);
  EXPECT_EQ(pts[0].id, -1);
  EXPECT_EQ(pts[1].position_mm, Eigen::Vector3d(4, 5.25, -6));
  EXPECT_EQ(pts[1].line, 7);

  const auto with_ids = read_text("x_mm,y_mm,z_mm,id\n0,0,0,17\n1,0,0,3\n");
  ASSERT_EQ(with_ids.size(), 2u);
  EXPECT_EQ(with_ids[0].id, 17);
  EXPECT_EQ(with_ids[1].id, 3);
  // Points 1e-6 mm apart are distinct (the duplicate tolerance is 1e-9 mm).
  EXPECT_EQ(read_text("x_mm,y_mm,z_mm\n1,2,3\n1.000001,2,3\n1,2,3.000001\n").size(), 3u);
  // Far-out but finite coordinates are numbers like any other.
  EXPECT_EQ(read_text("x_mm,y_mm,z_mm\n1e300,0,0\n-1e300,0,0\n0,1e300,-1e300\n").size(), 3u);
}

TEST(PointCloudReader, ErrorsNameFileLineColumnAndField) {
  const std::string h = "# comment\nx_mm,y_mm,z_mm\n"; // data starts on line 3
  EXPECT_ERROR(read_text(h + "1,2,3\n4,nan,6\n"), "cloud.csv:4:3: y_mm: 'nan' is not finite");
  EXPECT_ERROR(read_text(h + "1,2,3\n4,5,-inf\n"), "cloud.csv:4:5: z_mm: '-inf' is not finite");
  EXPECT_ERROR(read_text(h + "1,2,3\n4,5,six\n"), "cloud.csv:4:5: z_mm: 'six' is not a number");
  EXPECT_ERROR(read_text(h + "1,2,3\n4,5,6mm\n"), "cloud.csv:4:5: z_mm: '6mm' is not a number");
  EXPECT_ERROR(read_text(h + "1,,3\n"), "cloud.csv:3:3: y_mm: empty field");
  EXPECT_ERROR(read_text(h + "1,2\n"), "cloud.csv:3:4: row: 2 fields, expected 3");
  EXPECT_ERROR(read_text(h + "1,2,3\n\n1,2,3,4\n"), "cloud.csv:5:7: row: 4 fields, expected 3");
  EXPECT_ERROR(read_text(h + "1,2,3\n0,0,0\n1,2,3\n"),
               "cloud.csv:5:1: point: (1, 2, 3) duplicates the point on line 3");
  EXPECT_ERROR(read_text(h + "1,2,3\n1.0000000000001,2,3\n"), "cloud.csv:4:1: point:");
  EXPECT_ERROR(read_text(h + "0,0,0\n1e-10,-1e-10,0\n"), "duplicates the point on line 3");
  EXPECT_ERROR(read_text(h + "5,5,5\n0,0,0\n0,0,0\n5,5,5\n"), // the earliest repeating line wins
               "cloud.csv:5:1: point: (0, 0, 0) duplicates the point on line 4");
  EXPECT_ERROR(read_text(h + "1,2,3\n1,2,3\n4,5,nan\n"), "cloud.csv:5:5: z_mm:"); // syntax before repeats
  EXPECT_ERROR(read_text(h + "1e400,2,3\n"), "cloud.csv:3:1: x_mm: '1e400' is out of range");
  EXPECT_ERROR(read_text("x,y,z\n1,2,3\n"), "cloud.csv:1:1: header: expected 'x_mm', found 'x'");
  EXPECT_ERROR(read_text("\n#c\nx_mm,y_mm,zz\n1,2,3\n"), "cloud.csv:3:11: header: expected 'z_mm', found 'zz'");
  EXPECT_ERROR(read_text("x_mm,y_mm\n"), "cloud.csv:1:10: header: missing column 'z_mm'");
  EXPECT_ERROR(read_text("x_mm,y_mm,z_mm,tooth\n"), "cloud.csv:1:16: header: unexpected column 'tooth'");
  EXPECT_ERROR(read_text("1,2,3\n"), "cloud.csv:1:1: header: expected 'x_mm', found '1'");
  EXPECT_ERROR(read_text("# only a comment\n"), "cloud.csv:2:1: header: missing header x_mm,y_mm,z_mm");
  EXPECT_ERROR(read_text("x_mm,y_mm,z_mm\n# nothing\n"), "cloud.csv:1:1: header: no points follow the header");
  EXPECT_ERROR(read_text("x_mm,y_mm,z_mm,id\n1,2,3,7\n4,5,6,7\n"), "cloud.csv:3:7: id: 7 repeats the id on line 2");
  EXPECT_ERROR(read_text("x_mm,y_mm,z_mm,id\n1,2,3,9\n4,5,6,8\n7,8,9,8\n0,0,0,9\n"),
               "cloud.csv:4:7: id: 8 repeats the id on line 3");
  EXPECT_ERROR(read_text("x_mm,y_mm,z_mm,id\n1,2,3,-1\n"), "cloud.csv:2:7: id: '-1' is not a whole number >= 0");
  EXPECT_ERROR(surfaces::read_point_cloud(std::filesystem::path("/nonexistent/cloud.csv")),
               "/nonexistent/cloud.csv: cannot open");
}

/// Points on known flanks at known offsets, as CSV text (17 significant digits: exact round trip).
struct KnownPoint {
  int tooth;
  Flank flank;
  double xi, z, delta;
};

std::string cloud_text(const gears::InvoluteHelicoid& h, const std::vector<KnownPoint>& pts) {
  std::string s = "# generated on the nominal flanks\nx_mm,y_mm,z_mm\n";
  for (const auto& k : pts) {
    const gears::FlankPoint fp = h.at(k.tooth, k.flank, k.xi, k.z);
    const Eigen::Vector3d p = fp.p + k.delta * fp.n;
    s += g17(p.x()) + "," + g17(p.y()) + "," + g17(p.z()) + "\n";
  }
  return s;
}

TEST_F(GearPointTest, AssignToFlanksRecoversToothFlankDiameterZAndDistance) {
  std::vector<KnownPoint> known;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> uxi(xi_ff() + 0.01, xi_a() - 0.01), uz(0.01, 149.99);
  const double deltas[] = {-0.3, -0.05, -0.002, 0.0, 0.002, 0.05, 0.3};
  for (int tooth = 1; tooth <= 35; ++tooth)
    for (Flank flank : {Flank::Left, Flank::Right})
      for (double delta : deltas) known.push_back({tooth, flank, uxi(rng), uz(rng), delta});
  // The corners of the evaluated flank are inside.
  known.push_back({4, Flank::Right, xi_ff(), 0.0, 0.01});
  known.push_back({4, Flank::Left, xi_a(), 150.0, -0.01});

  const auto cloud = read_text(cloud_text(*flanks_, known), "probe.csv");
  ASSERT_EQ(cloud.size(), known.size());
  const auto samples = surfaces::assign_to_flanks(cloud, *flanks_, 0.5, "probe.csv");
  ASSERT_EQ(samples.size(), known.size());
  for (size_t i = 0; i < known.size(); ++i) {
    const auto& k = known[i];
    const auto& s = samples[i];
    EXPECT_EQ(s.tooth, k.tooth) << i;
    EXPECT_EQ(s.flank, k.flank) << i;
    EXPECT_NEAR(s.roll_length_mm, k.xi, 1e-7) << i;
    EXPECT_NEAR(s.diameter_mm, geometry_->diameter_at_roll_length(k.xi), 1e-7) << i;
    EXPECT_NEAR(s.z_mm, k.z, 1e-7) << i;
    EXPECT_NEAR(s.normal_distance_mm, k.delta, 1e-9) << i;
    EXPECT_EQ(s.line, static_cast<std::int64_t>(i) + 3);
  }
}

TEST_F(GearPointTest, AssignToFlanksRejectsPointsOffTheFlankNamingTheLine) {
  const double xm = 0.5 * (xi_ff() + xi_a());
  const auto run = [&](const KnownPoint& bad) {
    // Two good points first: the bad one is on line 5.
    const std::vector<KnownPoint> pts = {{1, Flank::Left, xm, 10, 0.01}, {2, Flank::Right, xm, 20, -0.01}, bad};
    return error_of(
        [&] { surfaces::assign_to_flanks(read_text(cloud_text(*flanks_, pts), "p.csv"), *flanks_, 0.5, "p.csv"); });
  };
  auto expect = [](const std::string& msg, const std::string& want) {
    EXPECT_NE(msg.find(want), std::string::npos) << "message: '" << msg << "'\nexpected: '" << want << "'";
  };
  expect(run({3, Flank::Right, xm, 50, 0.8}), "p.csv:5:1: point: ");
  expect(run({3, Flank::Right, xm, 50, 0.8}), "is off the flank: normal distance 0.8000 mm exceeds 0.5000 mm");
  expect(run({3, Flank::Left, xm, 50, -0.51}),
         "normal distance -0.5100 mm exceeds 0.5000 mm (foot on tooth 3 left flank");
  expect(run({3, Flank::Right, xm, -0.5, 0.0}), "p.csv:5:1: point: ");
  expect(run({3, Flank::Right, xm, -0.5, 0.0}), "projects outside the face width 0..150.000 mm");
  expect(run({3, Flank::Right, xm, 150.5, 0.0}), "projects outside the face width");
  const double xi_over_tip = geometry_->roll_length_at(geometry_->tip_diameter_mm() + 0.5);
  expect(run({3, Flank::Right, xi_over_tip, 50, 0.0}), "projects outside d_Ff..d_a");
  const double xi_under_ff = geometry_->roll_length_at(geometry_->root_form_diameter_mm() - 0.5);
  expect(run({3, Flank::Left, xi_under_ff, 50, 0.0}), "p.csv:5:1: point: ");
  expect(run({3, Flank::Left, xi_under_ff, 50, 0.0}), "projects outside d_Ff..d_a");
  // Within the tolerance (10 µm) of the edges is accepted.
  EXPECT_EQ(run({3, Flank::Right, xm, -0.005, 0.0}), "");

  // On the axis: inside the base cylinder, locate refuses.
  const std::string axis = error_of([&] {
    surfaces::assign_to_flanks(read_text("x_mm,y_mm,z_mm\n\n0,0,50\n", "a.csv"), *flanks_, 0.5, "a.csv");
  });
  expect(axis, "a.csv:3:1: point: (0.0000, 0.0000, 50.0000) does not project onto a flank");
  EXPECT_THROW(surfaces::assign_to_flanks({}, *flanks_, 0.0, "x"), std::invalid_argument);
}

} // namespace
