// The gear mesh: closed, normals out, flanks on the exact helicoid, and readable by OpenMesh in every format.
#include "geartopo/surfaces/gear_mesh.hpp"

#include "geartopo/gears/involute_helicoid.hpp"
#include "../gears/gear_fixtures.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <filesystem>

using namespace geartopo;

namespace {

class GearMeshTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    geometry_ = new gears::GearGeometry(geartopo::test::paper_gear());
    mesh_ = new surfaces::TriangleMesh(surfaces::gear_mesh(*geometry_, options_));
  }
  static void TearDownTestSuite() {
    delete mesh_;
    delete geometry_;
  }
  static inline surfaces::GearMeshOptions options_{};
  static inline gears::GearGeometry* geometry_ = nullptr;
  static inline surfaces::TriangleMesh* mesh_ = nullptr;
};

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

} // namespace

TEST_F(GearMeshTest, CountsFollowTheSections) {
  const long n = surfaces::section_point_count(*geometry_, options_);
  EXPECT_EQ(mesh_->vertices.cols(), n * options_.slices + 2);
  EXPECT_EQ(mesh_->faces.cols(), 2 * n * (options_.slices - 1) + 2 * n);
}

// Outward normals make the divergence-theorem volume positive; a helical sweep keeps the transverse area
// (Cavalieri), so the volume is area × b up to the chords between sections.
TEST_F(GearMeshTest, VolumeIsPositiveAndEqualsSectionAreaTimesFaceWidth) {
  const double b = geometry_->spec().face_width_mm;
  const long n = surfaces::section_point_count(*geometry_, options_);
  double area2 = 0.0;
  for (long i = 0; i < n; ++i) {
    const Eigen::Vector3d p = mesh_->vertices.col(i), q = mesh_->vertices.col((i + 1) % n);
    area2 += p.x() * q.y() - p.y() * q.x();
  }
  const double volume = surfaces::signed_volume(*mesh_);
  EXPECT_GT(volume, 0.0);
  EXPECT_NEAR(volume / (0.5 * area2 * b), 1.0, 1e-4);
}

// Each face on a flank faces the same way as the exact flank normal, and its vertices lie on the helicoid.
TEST_F(GearMeshTest, FlankFacesFaceOutAlongTheHelicoidNormal) {
  const gears::InvoluteHelicoid flanks(*geometry_);
  int on_flank = 0;
  for (Eigen::Index f = 0; f < mesh_->faces.cols(); ++f) {
    const Eigen::Vector3d a = mesh_->vertices.col(mesh_->faces(0, f)), b = mesh_->vertices.col(mesh_->faces(1, f)),
                          c = mesh_->vertices.col(mesh_->faces(2, f));
    const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    const double r = std::hypot(centroid.x(), centroid.y());
    if (r < 0.5 * geometry_->root_form_diameter_mm() + 0.5 || r > 0.5 * geometry_->tip_diameter_mm() - 0.5) continue;
    const auto loc = flanks.locate(centroid);
    if (!loc || std::abs(loc->normal_distance_mm) > 0.05) continue; // not a flank face
    ++on_flank;
    EXPECT_GT(normal.dot(loc->normal), 0.99) << "face " << f;
    EXPECT_NEAR(flanks.locate(a)->normal_distance_mm, 0.0, 1e-9);
  }
  EXPECT_GT(on_flank, 2 * 35 * (options_.flank_points - 3) * (options_.slices - 1));
}

TEST_F(GearMeshTest, EveryFormatReadsBackClosedWithTheSameFaces) {
  const auto dir = std::filesystem::temp_directory_path() / "geartopo_mesh_test";
  std::filesystem::create_directories(dir);
  for (const char* ext : {".ply", ".obj", ".stl", ".off"}) {
    const auto file = dir / (std::string("gear") + ext);
    surfaces::write_mesh(*mesh_, file);
    OMesh om;
    OpenMesh::IO::Options opts;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(om, file.string(), opts)) << ext;
    EXPECT_EQ(static_cast<long>(om.n_faces()), mesh_->faces.cols()) << ext;
    // Closed: no boundary edge, so no gaps between teeth, flanks, tip, root and end faces.
    long boundary = 0;
    for (auto e : om.edges()) boundary += om.is_boundary(e);
    EXPECT_EQ(boundary, 0) << ext;
    // Normals out, as read back: the volume stays positive.
    double v6 = 0.0;
    for (auto fh : om.faces()) {
      auto it = om.cfv_iter(fh);
      const auto p0 = om.point(*it++), p1 = om.point(*it++), p2 = om.point(*it);
      v6 += OpenMesh::dot(p0, OpenMesh::cross(p1, p2));
    }
    EXPECT_NEAR(v6 / 6.0 / surfaces::signed_volume(*mesh_), 1.0, 1e-5) << ext;
  }
  std::filesystem::remove_all(dir);
}

TEST(GearMesh, VertexValuesTravelInPly) {
  surfaces::TriangleMesh m;
  m.vertices.resize(3, 3);
  m.vertices << 0, 1, 0, 0, 0, 1, 0, 0, 0;
  m.faces.resize(3, 1);
  m.faces << 0, 1, 2;
  m.vertex_values = Eigen::Vector3d(1.5, -2.0, 3.25);
  m.value_name = "deviation_um";
  const auto file = std::filesystem::temp_directory_path() / "geartopo_values.ply";
  surfaces::write_mesh(m, file);
  OMesh om;
  OpenMesh::VPropHandleT<float> prop;
  om.add_property(prop, "deviation_um");
  om.property(prop).set_persistent(true);
  OpenMesh::IO::Options opts = OpenMesh::IO::Options::Custom;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(om, file.string(), opts));
  ASSERT_EQ(om.n_vertices(), 3u);
  EXPECT_FLOAT_EQ(om.property(prop, OMesh::VertexHandle(2)), 3.25f);
  std::filesystem::remove(file);
}

TEST(GearMesh, UnknownExtensionIsRefused) {
  surfaces::TriangleMesh m;
  EXPECT_THROW(surfaces::write_mesh(m, "/tmp/x.xyz"), std::runtime_error);
  EXPECT_FALSE(surfaces::is_mesh_extension("a.vtk"));
  EXPECT_TRUE(surfaces::is_mesh_extension("A.PLY"));
}
