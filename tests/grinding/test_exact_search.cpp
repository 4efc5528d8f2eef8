// The exact method's stroke search (src/grinding/flank_deviation.cpp): the parabolic shortcut of FlankDeviation::at
// against Brent's search run to a far tighter tolerance, on the whole flank (the active profile, not only the
// evaluation range, and the full face width), for realistic errors, for errors ten times larger, and for wheel
// poses whose deepest cut lies beyond the shortcut's reach (the fallback).
#include "grinding_fixture.hpp"

#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/machine/chain.hpp"

#include <atomic>
#include <cmath>
#include <cstdio>

using namespace geartopo;
using grinding::FlankDeviation;
using grinding::Method;
using test::kDatumZ;
using test::ModifiedProcess;
using test::random_machine;
using test::paper_setup;

namespace {

// Counts the wheel poses a search asks for.
class Counting final : public grinding::GrindingProcess {
public:
  explicit Counting(const grinding::GrindingProcess& inner) : inner_(inner) {}
  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override {
    ++poses;
    return inner_.actual_wMg(pp);
  }
  machine::Vector6d error_twist_w(const grinding::PathPoint& pp) const override { return inner_.error_twist_w(pp); }
  double wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const override {
    return inner_.wheel_radius_error_mm(v, pp);
  }
  mutable std::atomic<long> poses{0};

private:
  const grinding::GrindingProcess& inner_;
};

struct Comparison {
  double worst_mm = 0.0;       // largest |shortcut − reference|
  double most_below_mm = 0.0;  // largest amount by which the shortcut is below the reference (it never should be)
  double range_mm = 0.0;       // spread of the deviations, to show the errors do show
  double poses_per_point = 0.0;
  int unreached = 0;           // points the wheel never reaches (deviation +∞ from both searches)
};

// 15 × 15 points over the active flank and the full face width, both flanks of teeth 1, 12 and 24.
void compare(const grinding::GrindingProcess& process, Comparison& c) {
  const auto& s = paper_setup();
  const Counting counting(process);
  const FlankDeviation dev(s.flanks(), s.wheel(), s.path(), counting);
  const FlankDeviation reference(s.flanks(), s.wheel(), s.path(), process);
  const auto& r = s.ranges();
  const double b = s.geometry().spec().face_width_mm;
  double lo = 1e9, hi = -1e9;
  int points = 0;
  for (int tooth : {1, 12, 24})
    for (auto flank : {geartopo::Flank::Left, geartopo::Flank::Right})
      for (int i = 0; i < 15; ++i)
        for (int j = 0; j < 15; ++j) {
          const double xi = r.xi_active_start_mm + (r.xi_active_end_mm - r.xi_active_start_mm) * i / 14.0;
          const double z = b * j / 14.0;
          const double fast = dev.at(tooth, flank, xi, z, Method::Exact).deviation_mm;
          const double ref = reference.exact_by_brent(tooth, flank, xi, z, 1e-7).deviation_mm;
          ++points;
          // Where the wheel never reaches the point's normal line (beyond the wheel's profile), both say so.
          ASSERT_EQ(std::isfinite(fast), std::isfinite(ref)) << "tooth " << tooth << " xi " << xi << " z " << z;
          if (!std::isfinite(ref)) {
            ++c.unreached;
            continue;
          }
          c.worst_mm = std::max(c.worst_mm, std::abs(fast - ref));
          c.most_below_mm = std::max(c.most_below_mm, ref - fast);
          lo = std::min(lo, ref), hi = std::max(hi, ref);
        }
  c.range_mm = hi - lo;
  c.poses_per_point = static_cast<double>(counting.poses.load()) / points;
  std::printf("shortcut vs Brent(1e-7 mm): worst %.1e mm, most below %.1e mm, range %.4f mm, %.2f poses per point, "
              "%d of %d points not reached\n",
              c.worst_mm, c.most_below_mm, c.range_mm, c.poses_per_point, c.unreached, points);
}

} // namespace

// Realistic errors (≤ 50 µm, 100 µrad): the shortcut equals the tight search to 1e-6 µm and needs 4 poses a point.
TEST(ExactSearch, ParabolicShortcutMatchesATightBrentSearch) {
  const auto model = random_machine(1.0, 11);
  const grinding::MachineProcess process(model, kDatumZ);
  Comparison c;
  compare(process, c);
  EXPECT_GT(c.range_mm, 5e-3);
  EXPECT_LT(c.worst_mm, 1e-9);      // 1e-6 µm
  EXPECT_LT(c.most_below_mm, 1e-12); // a depth found is a real depth: never below the minimum
  EXPECT_EQ(c.unreached, 0);
  EXPECT_LT(c.poses_per_point, 4.05) << "the shortcut should decide almost everywhere";
}

// Ten times larger (≤ 0.5 mm, 1 mrad): still exact, whichever way each point is decided.
TEST(ExactSearch, LargeErrorsStayExact) {
  const auto model = random_machine(10.0, 5);
  const grinding::MachineProcess process(model, kDatumZ);
  Comparison c;
  compare(process, c);
  EXPECT_GT(c.range_mm, 5e-2);
  EXPECT_LT(c.worst_mm, 1e-8);
  EXPECT_LT(c.most_below_mm, 1e-12);
}

// A wheel moved along the gear's screw by s leaves the flank unchanged but puts every deepest cut s away from Z₀:
// beyond the shortcut's 0.45 mm reach (0.7 mm) and beyond Brent's first window (2 mm), the fallback must find it.
TEST(ExactSearch, DeepestCutFarFromTheNominalStrokeIsFound) {
  const double k = paper_setup().geometry().twist_rad_per_mm();
  for (double shift : {0.3, 0.7, 2.0}) {
    const ModifiedProcess screw([k, shift](const grinding::PathPoint& pp) {
      machine::AxisPose q = pp.q;
      q.z += shift;
      q.c -= k * shift;
      return machine::ideal_wMg(q);
    });
    Comparison c;
    compare(screw, c);
    EXPECT_LT(c.worst_mm, 1e-8) << "shift " << shift;
    EXPECT_LT(c.range_mm, 1e-8) << "shift " << shift << ": a screw motion must leave the flank unchanged";
    if (shift > FlankDeviation::kParabolaReachMm) {
      EXPECT_GT(c.poses_per_point, 10.0) << "the fallback must have decided";
    }
  }
}

// Where errors move the wheel's profile off the active flank's edge, no ground surface exists there: the simulation
// says which point instead of writing +∞ (or a NaN from it) into the topology and the ISO evaluation.
TEST(ExactSearch, APointTheWheelNeverReachesIsNamed) {
  const auto model = random_machine(10.0, 5);
  const grinding::MachineProcess process(model, kDatumZ);
  std::vector<std::string> messages;
  for (int threads : {1, 4}) {
    grinding::SimulationOptions o;
    o.teeth = {1, 12, 24};
    o.profile_points = 20;
    o.helix_points = 20;
    o.threads = threads;
    try {
      (void)grinding::simulate_topology(paper_setup(), process, o);
      ADD_FAILURE() << "a topology with unreached points was accepted";
    } catch (const std::runtime_error& e) {
      messages.push_back(e.what());
      EXPECT_NE(messages.back().find("the wheel never reaches this point"), std::string::npos) << e.what();
      EXPECT_NE(messages.back().find(" flank at d = "), std::string::npos) << e.what();
    }
  }
  ASSERT_EQ(messages.size(), 2u);
  EXPECT_EQ(messages[0], messages[1]) << "the point named must not depend on the thread count";
  // The first-order model has no such notion and stays finite.
  for (const auto& ft : test::simulate(process, Method::Linear, {1}))
    for (const auto& p : ft.profile) EXPECT_TRUE(std::isfinite(p.deviation_um));
}
