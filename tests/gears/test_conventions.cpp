// docs/conventions.md, pinned down: workpiece frame, tooth numbering, left/right flank, hand, plus material.
#include "gear_fixtures.hpp"

#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/gears/involute_helicoid.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

using namespace geartopo;
using geartopo::Flank;

namespace {
const gears::GearGeometry& paper() {
  static const gears::GearGeometry g(geartopo::test::paper_gear());
  return g;
}
double mid_xi(const gears::GearGeometry& g) { return g.roll_length_at(g.reference_diameter_mm()); }
} // namespace

// Tooth 1's centre line passes through +x at the datum face (z = 0).
TEST(Conventions, ToothOneIsOnPlusXAtTheDatumFace) {
  const gears::InvoluteHelicoid f(paper());
  const auto l = f.at(1, Flank::Left, mid_xi(paper()), 0.0).p, r = f.at(1, Flank::Right, mid_xi(paper()), 0.0).p;
  const Eigen::Vector3d mid = 0.5 * (l + r);
  EXPECT_NEAR(std::atan2(mid.y(), mid.x()), 0.0, 1e-12);
  EXPECT_GT(mid.x(), 0.0);
}

// Seen from the datum face the viewer looks along +z; teeth are numbered clockwise for that viewer, which is the
// positive sense of rotation about +z.
TEST(Conventions, TeethAreNumberedClockwiseSeenFromTheDatumFace) {
  const gears::InvoluteHelicoid f(paper());
  const Eigen::Vector3d view = Eigen::Vector3d::UnitZ(); // viewer at z < 0 looking at the datum face
  for (int t = 1; t < paper().teeth(); ++t) {
    const Eigen::Vector3d a = f.at(t, Flank::Left, mid_xi(paper()), 0.0).p;
    const Eigen::Vector3d b = f.at(t + 1, Flank::Left, mid_xi(paper()), 0.0).p;
    // Clockwise for the viewer: a × b points away from the viewer, along the view direction.
    EXPECT_GT(a.cross(b).dot(view), 0.0) << "tooth " << t;
  }
}

// Seen from the datum face with the tooth tip up, the left flank is on the viewer's left (DIN ISO 21771).
TEST(Conventions, LeftFlankIsOnTheLeftSeenFromTheDatumFaceTipUp) {
  const gears::InvoluteHelicoid f(paper());
  for (int t : {1, 9, 18, 27}) {
    const Eigen::Vector3d l = f.at(t, Flank::Left, mid_xi(paper()), 0.0).p;
    const Eigen::Vector3d r = f.at(t, Flank::Right, mid_xi(paper()), 0.0).p;
    const Eigen::Vector3d forward = Eigen::Vector3d::UnitZ();                 // viewing direction
    const Eigen::Vector3d up = (0.5 * (l + r)).cwiseProduct(Eigen::Vector3d(1, 1, 0)).normalized(); // tip up
    const Eigen::Vector3d right = forward.cross(up);                           // camera convention
    EXPECT_LT(l.dot(right), r.dot(right)) << "tooth " << t;
  }
}

// Flank normals point out of the material: a small step along n leaves the tooth (the transverse tooth thickness
// there is exceeded), and the normal deviation of that point is positive ("plus material").
TEST(Conventions, NormalsPointOutOfTheMaterialAndPlusMaterialIsPositive) {
  const gears::InvoluteHelicoid f(paper());
  for (Flank side : {Flank::Left, Flank::Right}) {
    const auto fp = f.at(5, side, mid_xi(paper()), 30.0);
    const double centre = f.tooth_centre_angle(5, 30.0);
    auto half_angle_of = [&](const Eigen::Vector3d& p) {
      return std::abs(std::remainder(std::atan2(p.y(), p.x()) - centre, 2 * std::numbers::pi));
    };
    EXPECT_GT(half_angle_of(fp.p + 0.01 * fp.n), half_angle_of(fp.p));
    EXPECT_NEAR(f.locate(fp.p + 0.01 * fp.n)->normal_distance_mm, 0.01, 1e-12);
  }
}

// A right-hand helix turns clockwise (seen from the datum face, i.e. positively about +z) as it goes into the gear.
TEST(Conventions, RightHandHelixAdvancesPositivelyAboutTheAxis) {
  const gears::InvoluteHelicoid f(paper());
  EXPECT_GT(f.tooth_centre_angle(1, 100.0), f.tooth_centre_angle(1, 0.0));
  EXPECT_NEAR(f.tooth_centre_angle(1, paper().lead_mm()), 2 * std::numbers::pi, 1e-12);
  auto lh = geartopo::test::paper_gear();
  lh.helix_angle_rad *= -1;
  const gears::GearGeometry glh(lh);
  const gears::InvoluteHelicoid flh(glh);
  EXPECT_LT(flh.tooth_centre_angle(1, 100.0), 0.0);
}
