// The form wheel and the wheel path, against the geometry that defines them.
#include "grinding_fixture.hpp"

#include "geartopo/gears/involute_helicoid.hpp"
#include "geartopo/core/field_error.hpp"
#include "geartopo/machine/chain.hpp"

#include <numbers>

using namespace geartopo;
using test::paper_setup;

// Profile grinding's contact condition: along the synthesized contact line the flank normal meets the wheel axis,
// and the wheel surface passes through the contact point.
TEST(FormWheel, ContactLineSatisfiesTheContactCondition) {
  const auto& s = paper_setup();
  const auto& wheel = s.wheel();
  const machine::Pose& wMg = wheel.reference_wMg();
  const Eigen::Vector3d O = wMg.translation(), u = wMg.linear().col(1);
  const auto& r = s.ranges();
  for (auto [tooth, flank] : {std::pair{1, geartopo::Flank::Right}, std::pair{2, geartopo::Flank::Left}}) {
    for (int i = 0; i <= 20; ++i) {
      const double xi = r.xi_active_start_mm + (r.xi_active_end_mm - r.xi_active_start_mm) * i / 20.0;
      const auto fp = s.flanks().at(tooth, flank, xi, wheel.contact_offset_mm(flank, xi));
      // Distance between the normal line and the wheel axis (skew-line distance), mm.
      const Eigen::Vector3d w = fp.n.cross(u);
      EXPECT_NEAR(std::abs((fp.p - O).dot(w)) / w.norm(), 0.0, 1e-7);
      const Eigen::Vector3d q = wMg.inverse() * fp.p;
      EXPECT_NEAR(std::hypot(q.x(), q.z()), wheel.radius(q.y()), 1e-7);
    }
  }
}

// With the wheel centred on the space (Y = 0) a helical space is symmetric under a half turn about the common
// perpendicular, so the wheel profile is symmetric: R(v) = R(−v). Its largest radius reaches the root.
TEST(FormWheel, ProfileIsSymmetricAndReachesTheRoot) {
  const auto& w = paper_setup().wheel();
  for (double v = 0.0; v < std::min(-w.v_min(), w.v_max()); v += 0.25) EXPECT_NEAR(w.radius(v), w.radius(-v), 1e-6) << v;
  EXPECT_NEAR(w.radius(0.0), 175.0, 1e-9);
  EXPECT_TRUE(std::isinf(w.radius(w.v_max() + 1.0)));
}

// C follows the lead: the common perpendicular of wheel axis and gear axis stays on the space's centre line.
TEST(WheelPath, TheWheelFollowsTheSpaceCentreLine) {
  const auto& s = paper_setup();
  const auto& g = s.geometry();
  for (int space : {1, 7, 35})
    for (double z : {-20.0, 0.0, 75.0, 170.0}) {
      const machine::AxisPose q = s.path().commanded(space, z);
      const machine::Pose wMg = machine::ideal_wMg(q);
      // Foot of the common perpendicular: wheel centre minus Y along the axis.
      const Eigen::Vector3d foot = wMg.translation() - q.y * wMg.linear().col(1);
      const double centre = (space - 0.5) * 2 * std::numbers::pi / g.teeth() + g.twist_rad_per_mm() * z;
      EXPECT_NEAR(std::remainder(std::atan2(foot.y(), foot.x()) - centre, 2 * std::numbers::pi), 0.0, 1e-12);
      EXPECT_NEAR(foot.z(), z, 1e-12);
      EXPECT_NEAR(std::hypot(foot.x(), foot.y()), s.setting().centre_distance_mm, 1e-9);
    }
  EXPECT_NEAR(s.setting().tilt_rad, -30.0 * std::numbers::pi / 180.0, 1e-15); // right hand: A = −β
}

TEST(WheelPath, StrokesCoverTheFaceAndTimeRunsForward) {
  grinding::ProcessSpec p;
  p.index_step = 4; // skip indexing: 1, 5, 9, …
  p.direction = grinding::StrokeDirection::Alternate;
  p.feed_mm_per_min = 600.0;
  p.indexing_time_s = 3.0;
  const grinding::GrindingSetup s(test::paper_gear(), {350.0, 0.0}, p);
  const auto& strokes = s.path().strokes();
  ASSERT_EQ(strokes.size(), 35u);
  EXPECT_EQ(strokes[0].space, 1);
  EXPECT_EQ(strokes[1].space, 5);
  std::vector<int> seen(35, 0);
  for (size_t i = 0; i < strokes.size(); ++i) {
    ++seen[static_cast<size_t>(strokes[i].space - 1)];
    const double lo = std::min(strokes[i].z_begin_mm, strokes[i].z_end_mm), hi = std::max(strokes[i].z_begin_mm, strokes[i].z_end_mm);
    EXPECT_LE(lo, -s.wheel().max_contact_offset_mm() - p.overtravel_mm + 1e-9);
    EXPECT_GE(hi, 150.0 - s.wheel().min_contact_offset_mm() + p.overtravel_mm - 1e-9);
    EXPECT_EQ(strokes[i].z_end_mm > strokes[i].z_begin_mm, i % 2 == 0); // alternate: up, down, up, …
    EXPECT_NEAR(strokes[i].t_end_s - strokes[i].t_begin_s, (hi - lo) / 10.0, 1e-9); // 600 mm/min = 10 mm/s
    if (i > 0) {
      EXPECT_NEAR(strokes[i].t_begin_s, strokes[i - 1].t_end_s + 3.0, 1e-9);
    }
  }
  for (int n : seen) EXPECT_EQ(n, 1);
  // Time at a point of a downward stroke counts from its upper end.
  const auto& down = strokes[1];
  EXPECT_NEAR(s.path().time_at(down.space, down.z_begin_mm - 10.0), down.t_begin_s + 1.0, 1e-9);
}

TEST(WheelPath, IndexStepMustVisitEverySpace) {
  grinding::ProcessSpec p;
  p.index_step = 5; // gcd(5, 35) = 5
  EXPECT_THROW(grinding::GrindingSetup(test::paper_gear(), {350.0, 0.0}, p), geartopo::FieldError);
}
