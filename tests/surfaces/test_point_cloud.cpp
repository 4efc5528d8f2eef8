// Mesh distance (CGAL AABB tree, pseudo-normal sign), the point-cloud reader and the assignment of measured points to
// the exact nominal flanks. Tolerances are physical: exact answers for planar meshes, the chord (sag) bound of the
// triangulation for curved ones.
#include "geartopo/surfaces/gear_mesh.hpp"
#include "geartopo/surfaces/point_cloud.hpp"

#include "geartopo/gears/involute_helicoid.hpp"
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
using geartopo::Flank;

namespace {

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
  // Far-out coordinates up to 100 m are numbers like any other; beyond, no gear's (issue 31: a 1e300 reached a fit
  // as "noise level σ = inf µm", no file named): refused at its place.
  EXPECT_EQ(read_text("x_mm,y_mm,z_mm\n1e5,0,0\n-1e5,0,0\n0,1e5,-1e5\n").size(), 3u);
  EXPECT_ERROR(read_text("x_mm,y_mm,z_mm\n1,2,3\n0,1e300,0\n"),
               "cloud.csv:3:3: y_mm: '1e300' mm is beyond ±100000 mm, further than any gear reaches (a wrong unit?)");
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
