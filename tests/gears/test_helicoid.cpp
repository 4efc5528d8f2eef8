// The involute helicoid: identities every exact flank must satisfy, derivatives by finite differences, the
// inverse (point → tooth, flank, diameter, z), hand mirroring, and the flank motion under a C offset.
#include "gear_fixtures.hpp"

#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/gears/involute.hpp"
#include "geartopo/gears/involute_helicoid.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

using namespace geartopo;
using geartopo::Flank;

namespace {

// Loaded once for the whole suite (geometry-central style shared assets).
class HelicoidTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    geometry_ = new gears::GearGeometry(geartopo::test::paper_gear());
    flanks_ = new gears::InvoluteHelicoid(*geometry_);
  }
  static void TearDownTestSuite() {
    delete flanks_;
    delete geometry_;
  }
  struct Sample {
    int tooth;
    Flank flank;
    double xi, z;
  };
  static std::vector<Sample> samples(int n, unsigned seed = 7) {
    std::mt19937 rng(seed);
    const auto& g = *geometry_;
    std::uniform_real_distribution<double> xi(g.roll_length_at(g.root_form_diameter_mm()),
                                              g.roll_length_at(g.tip_diameter_mm()));
    std::uniform_real_distribution<double> z(0.0, g.spec().face_width_mm);
    std::uniform_int_distribution<int> tooth(1, g.teeth()), side(0, 1);
    std::vector<Sample> out;
    for (int i = 0; i < n; ++i) out.push_back({tooth(rng), side(rng) ? Flank::Right : Flank::Left, xi(rng), z(rng)});
    return out;
  }
  static gears::GearGeometry* geometry_;
  static gears::InvoluteHelicoid* flanks_;
};
gears::GearGeometry* HelicoidTest::geometry_ = nullptr;
gears::InvoluteHelicoid* HelicoidTest::flanks_ = nullptr;

} // namespace

TEST_F(HelicoidTest, NormalIsUnitAndPerpendicularToTangents) {
  for (const auto& s : samples(500)) {
    const auto fp = flanks_->at(s.tooth, s.flank, s.xi, s.z);
    EXPECT_NEAR(fp.n.norm(), 1.0, 1e-14);
    EXPECT_NEAR(fp.n.dot(fp.d_xi.normalized()), 0.0, 1e-13);
    EXPECT_NEAR(fp.n.dot(fp.d_z.normalized()), 0.0, 1e-13);
  }
}

// The normal line of an involute helicoid lies in a plane tangent to the base cylinder: it touches the base cylinder
// (closest distance to the axis = r_b) and is inclined by β_b to the transverse plane.
TEST_F(HelicoidTest, NormalLineIsTangentToBaseCylinderAndInclinedByBaseHelixAngle) {
  const double rb = 0.5 * geometry_->base_diameter_mm();
  for (const auto& s : samples(500)) {
    const auto fp = flanks_->at(s.tooth, s.flank, s.xi, s.z);
    // Distance from the z axis to the line p + t n: minimise |(p + t n)_xy|.
    const Eigen::Vector2d p = fp.p.head<2>(), n = fp.n.head<2>();
    const double t = -p.dot(n) / n.squaredNorm();
    EXPECT_NEAR((p + t * n).norm(), rb, 1e-9);
    EXPECT_NEAR(std::asin(std::abs(fp.n.z())), std::abs(geometry_->base_helix_angle()), 1e-12);
  }
}

TEST_F(HelicoidTest, RadiusAndPolarAngleFollowTheInvolute) {
  const auto& g = *geometry_;
  for (const auto& s : samples(200)) {
    const auto fp = flanks_->at(s.tooth, s.flank, s.xi, s.z);
    const double r = std::hypot(fp.p.x(), fp.p.y());
    EXPECT_NEAR(2 * r, g.diameter_at_roll_length(s.xi), 1e-9);
    EXPECT_NEAR(fp.p.z(), s.z, 1e-12);
    const double half = 0.5 * g.transverse_tooth_thickness_at(2 * r) / r; // half tooth angle at r
    const double expected = flanks_->tooth_centre_angle(s.tooth, s.z) + geartopo::side_sign(s.flank) * half;
    EXPECT_NEAR(std::remainder(std::atan2(fp.p.y(), fp.p.x()) - expected, 2 * std::numbers::pi), 0.0, 1e-12);
  }
}

TEST_F(HelicoidTest, DerivativesMatchFiniteDifferences) {
  for (const auto& s : samples(100)) {
    const auto fp = flanks_->at(s.tooth, s.flank, s.xi, s.z);
    for (double h : {1e-2, 1e-3}) {
      const Eigen::Vector3d dxi = (flanks_->at(s.tooth, s.flank, s.xi + h, s.z).p -
                                   flanks_->at(s.tooth, s.flank, s.xi - h, s.z).p) / (2 * h);
      const Eigen::Vector3d dz = (flanks_->at(s.tooth, s.flank, s.xi, s.z + h).p -
                                  flanks_->at(s.tooth, s.flank, s.xi, s.z - h).p) / (2 * h);
      // Central differences: error O(h²·|P'''|) with |P'''| ~ 1/r_b² for these radii.
      EXPECT_NEAR((dxi - fp.d_xi).norm(), 0.0, 10 * h * h / 260.0);
      EXPECT_NEAR((dz - fp.d_z).norm(), 0.0, 10 * h * h / 260.0);
    }
  }
}

TEST_F(HelicoidTest, LocateInvertsAtOffsetsAlongTheNormal) {
  for (const auto& s : samples(300)) {
    const auto fp = flanks_->at(s.tooth, s.flank, s.xi, s.z);
    for (double offset : {0.0, 0.05, -0.05, 0.5}) {
      const auto loc = flanks_->locate(fp.p + offset * fp.n);
      ASSERT_TRUE(loc.has_value());
      EXPECT_EQ(loc->tooth, s.tooth);
      EXPECT_EQ(loc->flank, s.flank);
      EXPECT_NEAR(loc->roll_length_mm, s.xi, 1e-8);
      EXPECT_NEAR(loc->z_mm, s.z, 1e-8);
      EXPECT_NEAR(loc->normal_distance_mm, offset, 1e-10);
      EXPECT_NEAR(loc->diameter_mm, geometry_->diameter_at_roll_length(s.xi), 1e-8);
    }
  }
}

TEST_F(HelicoidTest, LocateRefusesPointsInsideTheBaseCylinder) {
  EXPECT_FALSE(flanks_->locate(Eigen::Vector3d(100.0, 0.0, 10.0)).has_value());
  EXPECT_FALSE(flanks_->locate(Eigen::Vector3d(std::nan(""), 300.0, 10.0)).has_value());
}

// Right and left hand are mirror images: reflecting y → −y maps the right-hand gear onto the left-hand one, tooth j
// onto tooth 2 − j (mod z), and swaps the right and left flanks.
TEST(Helicoid, RightAndLeftHandMirrorEachOther) {
  auto rh = geartopo::test::paper_gear();
  auto lh = rh;
  lh.helix_angle_rad = -rh.helix_angle_rad;
  const gears::GearGeometry grh(rh), glh(lh);
  const gears::InvoluteHelicoid frh(grh), flh(glh);
  const int z = rh.teeth;
  for (int tooth : {1, 2, 18, 35}) {
    const int mirrored = ((z - (tooth - 1)) % z) + 1;
    for (Flank f : {Flank::Left, Flank::Right}) {
      const Flank other = f == Flank::Left ? Flank::Right : Flank::Left;
      for (double zz : {0.0, 75.0, 150.0}) {
        const auto a = frh.at(tooth, f, 40.0, zz);
        const auto b = flh.at(mirrored, other, 40.0, zz);
        const Eigen::Vector3d m(1.0, -1.0, 1.0);
        EXPECT_NEAR((a.p.cwiseProduct(m) - b.p).norm(), 0.0, 1e-9);
        EXPECT_NEAR((a.n.cwiseProduct(m) - b.n).norm(), 0.0, 1e-12);
      }
    }
  }
}

// A turn Δγ of the workpiece moves every flank point by Δγ e_z × P; along the normal that is ±r_b cos β_b Δγ:
// plus material on the right flank (it faces +θ), minus on the left. This is the reference answer for a
// pure C-axis offset.
TEST_F(HelicoidTest, RotationAboutTheAxisMovesFlanksByBaseRadiusTimesCosBetaB) {
  const double rb = 0.5 * geometry_->base_diameter_mm();
  const double cb = std::cos(geometry_->base_helix_angle());
  const double dgamma = 20e-6; // 20 µrad
  const Eigen::Matrix3d R = Eigen::AngleAxisd(dgamma, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (const auto& s : samples(200)) {
    const auto fp = flanks_->at(s.tooth, s.flank, s.xi, s.z);
    const auto loc = flanks_->locate_on(R * fp.p, s.tooth, s.flank);
    ASSERT_TRUE(loc.has_value());
    EXPECT_NEAR(loc->normal_distance_mm * 1e3, geartopo::side_sign(s.flank) * rb * cb * dgamma * 1e3, 1e-6); // µm
  }
}

// An axial shift Δz of a helical flank reads as a normal deviation ∓Δz sin β_b (right hand: the surface advances in
// θ with z, so moving it +z uncovers material on the right flank).
TEST_F(HelicoidTest, AxialShiftMovesFlanksBySinBetaB) {
  const double sb = std::sin(geometry_->base_helix_angle());
  const double dz = 0.01; // 10 µm
  for (const auto& s : samples(200)) {
    const auto fp = flanks_->at(s.tooth, s.flank, s.xi, s.z);
    const auto loc = flanks_->locate_on(fp.p + Eigen::Vector3d(0, 0, dz), s.tooth, s.flank);
    ASSERT_TRUE(loc.has_value());
    EXPECT_NEAR(loc->normal_distance_mm, -geartopo::side_sign(s.flank) * sb * dz, 1e-9);
  }
}
