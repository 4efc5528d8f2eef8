// The exact method's stroke search (src/grinding/flank_deviation.cpp): the parabolic shortcut of FlankDeviation::at
// against Brent's search run to a far tighter tolerance, on the whole flank (the active profile, not only the
// evaluation range, and the full face width), for realistic errors, for errors ten times larger, and for wheel
// poses whose deepest cut lies beyond the shortcut's reach (the fallback).
#include "grinding_fixture.hpp"

#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/machine/chain.hpp"

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

struct Comparison {
  double worst_mm = 0.0;       // largest |shortcut − reference|
  double most_below_mm = 0.0;  // largest amount by which the shortcut is below the reference (it never should be)
  double range_mm = 0.0;       // spread of the deviations, to show the errors do show
  double poses_per_point = 0.0;
  int unreached = 0;           // points the wheel never reaches (deviation +∞ from both searches)
};

// 15 × 15 points over the active flank and the full face width, both flanks of teeth 1, 12 and 24. With
// curvature_scale > 0 each target carries the ideal process's depth curvature times that factor (as TopologyPlan
// stores it, factor 1; another factor is a wrong curvature the guards must catch), so the 3-pose search runs.
void compare(const grinding::GrindingProcess& process, Comparison& c, double curvature_scale = 0.0) {
  const auto& s = paper_setup();
  const test::CountingPoses counting(process);
  const FlankDeviation dev(s.flanks(), s.wheel(), s.path(), counting);
  const FlankDeviation reference(s.flanks(), s.wheel(), s.path(), process);
  const grinding::IdealProcess ideal;
  const FlankDeviation ideal_dev(s.flanks(), s.wheel(), s.path(), ideal);
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
          auto target = dev.target(tooth, flank, xi, z);
          target.depth_curvature_per_mm = curvature_scale * ideal_dev.depth_curvature_per_mm(target);
          if (curvature_scale > 0.0) {
            EXPECT_GT(target.depth_curvature_per_mm, 0.0);
          }
          const double fast = dev.at(target, Method::Exact).deviation_mm;
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

// The 3-pose search (the depth's curvature known from the ideal process, as TopologyPlan gives it) against Brent's
// search run to 1e-7 mm in Z (truth: an independent search that knows nothing of the curvature), on realistic and
// tenfold errors, at the tolerances of the 4-pose search's tests; and with the curvature wrong by ±30 %, where the
// a-posteriori check must hand the points to the 4-pose search and the result must stay exact.
TEST(ExactSearch, KnownCurvatureSearchMatchesATightBrentSearch) {
  for (const double scale : {1.0, 10.0}) {
    const auto model = random_machine(scale, scale == 1.0 ? 11 : 5);
    const grinding::MachineProcess process(model, kDatumZ);
    for (const double curvature_scale : {1.0, 0.7, 1.3}) {
      Comparison c;
      compare(process, c, curvature_scale);
      EXPECT_GT(c.range_mm, 5e-3 * scale);
      EXPECT_LT(c.worst_mm, scale == 1.0 ? 1e-9 : 1e-8) << "errors ×" << scale << ", curvature ×" << curvature_scale;
      EXPECT_LT(c.most_below_mm, 1e-12);
      if (scale == 1.0 && curvature_scale == 1.0) {
        EXPECT_LT(c.poses_per_point, 3.05) << "the 3-pose vertex should decide almost everywhere";
      }
      if (curvature_scale != 1.0) {
        EXPECT_GT(c.poses_per_point, 3.5) << "a curvature 30 % wrong must be caught (4-pose search)";
      }
    }
  }
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

// Newton's stopping rule in FlankDeviation::entry_depth: it stops once its proven bound puts the depth within
// kNewtonTolMm (1e-10 µm) of the root, one step before the old rule (|step| < 1e-12 mm) would. The old rule is still
// what entry_depth does for a process that may change the wheel's radius, so a process saying so (with a zero radius
// error: the same function f, test::NewtonToRounding) runs Newton to rounding.
namespace {

// 30 × 30 points over the active flank and the full face width, both flanks of `teeth`.
template <class F>
void for_each_flank_point(std::initializer_list<int> teeth, F&& f) {
  const auto& s = paper_setup();
  const auto& r = s.ranges();
  const double b = s.geometry().spec().face_width_mm;
  for (int tooth : teeth)
    for (auto flank : {geartopo::Flank::Left, geartopo::Flank::Right})
      for (int i = 0; i < 30; ++i)
        for (int j = 0; j < 30; ++j)
          f(tooth, flank, r.xi_active_start_mm + (r.xi_active_end_mm - r.xi_active_start_mm) * i / 29.0, b * j / 29.0);
}

} // namespace

// The early stop against Newton run to rounding, at every depth the search asks for (entry_depth at Z₀ and ±0.3 mm)
// and at the deviations: within the bound (1e-13 mm) plus the rounding of the residual (|q| ~ 300 mm: ~1e-13 mm).
TEST(NewtonStop, EarlyStopAgreesWithNewtonRunToRounding) {
  const auto& s = paper_setup();
  for (double scale : {1.0, 10.0}) {
    const auto model = random_machine(scale, 23);
    const grinding::MachineProcess process(model, kDatumZ);
    const test::NewtonToRounding to_rounding(process);
    const FlankDeviation dev(s.flanks(), s.wheel(), s.path(), process), reference(s.flanks(), s.wheel(), s.path(), to_rounding);
    double worst_depth = 0.0, worst_deviation = 0.0;
    int finite = 0;
    for_each_flank_point({1, 12, 24}, [&](int tooth, geartopo::Flank flank, double xi, double z) {
      const auto target = dev.target(tooth, flank, xi, z);
      for (double dz : {-0.3, 0.0, 0.3}) {
        const auto pp = s.path().point(target.space, target.z0 + dz);
        const auto wMg = process.actual_wMg(pp);
        const double early = dev.entry_depth(target.fp, wMg, pp), full = reference.entry_depth(target.fp, wMg, pp);
        ASSERT_EQ(std::isfinite(early), std::isfinite(full));
        if (std::isfinite(full)) worst_depth = std::max(worst_depth, std::abs(early - full)), ++finite;
      }
      const double a = dev.at(target, Method::Exact).deviation_mm, b = reference.at(target, Method::Exact).deviation_mm;
      ASSERT_EQ(std::isfinite(a), std::isfinite(b));
      if (std::isfinite(b)) worst_deviation = std::max(worst_deviation, std::abs(a - b));
    });
    std::printf("scale %.0f: early stop vs Newton to rounding: depths %.1e mm (%d), deviations %.1e mm\n", scale,
                worst_depth, finite, worst_deviation);
    EXPECT_GT(finite, 15000);
    EXPECT_LT(worst_depth, 2e-13) << "scale " << scale;
    EXPECT_LT(worst_deviation, 1e-12) << "scale " << scale; // 1e-9 µm
  }
}

// A constant C-axis error Δγ turns the wheel by −Δγ about the gear axis, and an involute helicoid turned about its
// axis is its own parallel surface at r_b cos β_b Δγ (the involute's evolvent property): every right flank reads
// −r_b cos β_b Δγ, every left flank +r_b cos β_b Δγ more than without the error (the wheel's own small departure from
// the flank, common to both, cancels). Exact to the search's accuracy, so checked to 1e-6 µm at 30 × 30 points.
TEST(NewtonStop, ARigidTurnOfTheWheelGivesTheInvoluteOffsetToAMillionthOfAMicron) {
  const auto& s = paper_setup();
  const double dgamma = 20e-6;
  const auto turned = test::machine_with({machine::ErrorSource::constant(machine::ComponentId::epsilon_zc, 20.0, "urad")});
  const auto nominal = test::machine_with({});
  const grinding::MachineProcess p_turned(turned, kDatumZ), p_nominal(nominal, kDatumZ);
  const FlankDeviation dev(s.flanks(), s.wheel(), s.path(), p_turned), dev0(s.flanks(), s.wheel(), s.path(), p_nominal);
  const auto& g = s.geometry();
  const double offset_mm = 0.5 * g.base_diameter_mm() * std::cos(g.base_helix_angle()) * dgamma;
  double worst = 0.0;
  for_each_flank_point({1, 18}, [&](int tooth, geartopo::Flank flank, double xi, double z) {
    const double d = dev.at(tooth, flank, xi, z, Method::Exact).deviation_mm - dev0.at(tooth, flank, xi, z, Method::Exact).deviation_mm;
    worst = std::max(worst, std::abs(d + geartopo::side_sign(flank) * offset_mm));
  });
  std::printf("rigid turn of %.0f µrad: offset %.6f µm, worst departure %.1e µm\n", dgamma * 1e6, offset_mm * 1e3, worst * 1e3);
  EXPECT_LT(worst, 1e-9); // 1e-6 µm
}
