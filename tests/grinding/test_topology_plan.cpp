// The fast simulation path of Monte Carlo (TopologyPlan: the points' geometry computed once; MachineProcess: the
// chain's joints reused while their axes stand still) against the plain exact simulation: simulate_topology on a
// process that evaluates the whole chain afresh at every pose (machine::actual_wMg with a new MachineData, the
// evaluation before this optimisation). Truth: that plain computation. Bound: 1e-6 µm, the (the plan's
// search asks 3 poses per point from the stored depth curvature, the plain one 4: their vertices differ by
// ~1e-12 mm, tests/grinding/test_exact_search.cpp).
#include "grinding_fixture.hpp"

#include "geartopo/grinding/topology_plan.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/machine_data.hpp"
#include "geartopo/machine/transforms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace geartopo;

namespace {

/// MachineProcess as it was: the whole exact chain at every pose, a fresh workspace each time.
class FreshChainProcess final : public grinding::GrindingProcess {
public:
  FreshChainProcess(const machine::MachineModel& model, double z0) : model_(model), z0_(z0), twist_(model, z0) {}
  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override {
    machine::MachineData data;
    machine::AxisPose q = pp.q;
    q.z += z0_;
    return machine::translation(0.0, 0.0, -z0_) * machine::actual_wMg(model_, data, q);
  }
  /// The first-order twist is not part of the optimisation: the machine process's own.
  machine::Vector6d error_twist_w(const grinding::PathPoint& pp) const override { return twist_.error_twist_w(pp); }

private:
  const machine::MachineModel& model_;
  double z0_;
  grinding::MachineProcess twist_;
};

/// Commands that change along the stroke on every axis (as compensated commands do): X, Y, A and C move too, so
/// every joint of the evaluator is recomputed at some poses and reused at others.
class MovingCommands final : public grinding::GrindingProcess {
public:
  explicit MovingCommands(const grinding::GrindingProcess& inner) : inner_(inner) {}
  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override {
    grinding::PathPoint c = pp;
    const double step = std::floor(pp.z_stroke_mm / 7.0); // piecewise constant: runs of equal commands, then jumps
    c.q.x += 2e-3 * std::sin(step);
    c.q.y += 1e-3 * std::cos(step);
    c.q.a += 2e-5 * std::sin(0.1 * pp.z_stroke_mm);
    c.q.c += 1e-5 * std::cos(step);
    return inner_.actual_wMg(c);
  }
  machine::Vector6d error_twist_w(const grinding::PathPoint&) const override { return machine::Vector6d::Zero(); }

private:
  const grinding::GrindingProcess& inner_;
};

double largest_difference_um(const std::vector<grinding::FlankTopology>& a, const std::vector<grinding::FlankTopology>& b) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (size_t f = 0; f < a.size() && f < b.size(); ++f) {
    EXPECT_EQ(a[f].tooth, b[f].tooth);
    EXPECT_EQ(a[f].flank, b[f].flank);
    const auto compare = [&](const auto& pa, const auto& pb) {
      EXPECT_EQ(pa.size(), pb.size());
      for (size_t i = 0; i < pa.size() && i < pb.size(); ++i) {
        EXPECT_EQ(pa[i].roll_length_mm, pb[i].roll_length_mm);
        EXPECT_EQ(pa[i].diameter_mm, pb[i].diameter_mm);
        EXPECT_EQ(pa[i].z_mm, pb[i].z_mm);
        worst = std::max(worst, std::abs(pa[i].deviation_um - pb[i].deviation_um));
      }
    };
    compare(a[f].grid, b[f].grid);
    compare(a[f].profile, b[f].profile);
    compare(a[f].helix, b[f].helix);
    compare(a[f].dense, b[f].dense);
  }
  return worst;
}

grinding::SimulationOptions plan_options() {
  grinding::SimulationOptions o;
  o.teeth = {1, 2, 17};
  o.profile_points = 12;
  o.helix_points = 15;
  o.dense_rows = 3;
  o.dense_cols = 4;
  return o;
}

void expect_plan_matches_plain(const grinding::GrindingSetup& setup, const machine::MachineModel& model, bool moving) {
  const grinding::MachineProcess fast(model, test::kDatumZ);
  const FreshChainProcess plain(model, test::kDatumZ);
  const MovingCommands fast_moving(fast), plain_moving(plain);
  const grinding::GrindingProcess& f = moving ? static_cast<const grinding::GrindingProcess&>(fast_moving) : fast;
  const grinding::GrindingProcess& p = moving ? static_cast<const grinding::GrindingProcess&>(plain_moving) : plain;
  auto o = plan_options();
  for (const auto method : {grinding::Method::Exact, grinding::Method::Linear}) {
    if (method == grinding::Method::Linear && moving) continue; // the linear method uses the twist, not the pose
    o.method = method;
    o.threads = 1;
    const grinding::TopologyPlan plan(setup, o);
    const auto reference = grinding::simulate_topology(setup, p, o);
    const auto one = plan.simulate(f, 1), two = plan.simulate(f, 2);
    EXPECT_LE(largest_difference_um(one, reference), 1e-6);
    EXPECT_EQ(largest_difference_um(one, two), 0.0) << "threads changed the result";
    double largest = 0.0;
    for (const auto& ft : reference)
      for (const auto& pt : ft.grid) largest = std::max(largest, std::abs(pt.deviation_um));
    EXPECT_GT(largest, 1.0) << "the scene should have errors of several µm";
  }
}

} // namespace

TEST(TopologyPlan, EqualsThePlainExactSimulationOnARightHandGear) {
  expect_plan_matches_plain(test::paper_setup(), test::random_machine(1.0, 11), false);
}

TEST(TopologyPlan, EqualsThePlainExactSimulationOnALeftHandGear) {
  const grinding::GrindingSetup left(test::make_spec(6.0, 31, 20.0, -18.0, 0.1, 60.0), {300.0, 0.0}, {});
  expect_plan_matches_plain(left, test::random_machine(0.8, 5), false);
}

TEST(TopologyPlan, EqualsThePlainExactSimulationWhenEveryAxisMovesAlongTheStroke) {
  expect_plan_matches_plain(test::paper_setup(), test::random_machine(1.0, 23), true);
}

// Two models alternating in one thread (Monte Carlo: a new machine every sample): the per-thread evaluator must
// never reuse one model's joints for another, also when the second is built where the first was freed.
TEST(TopologyPlan, ModelsBuiltOneAfterAnotherAreNeverConfused) {
  auto o = plan_options();
  o.teeth = {5};
  const grinding::TopologyPlan plan(test::paper_setup(), o);
  for (unsigned seed : {3u, 4u, 3u}) {
    const auto model = std::make_unique<machine::MachineModel>(test::random_machine(1.0, seed));
    const grinding::MachineProcess fast(*model, test::kDatumZ);
    const FreshChainProcess plain(*model, test::kDatumZ);
    EXPECT_LE(largest_difference_um(plan.simulate(fast, 1), grinding::simulate_topology(test::paper_setup(), plain, o)), 1e-6)
        << "seed " << seed;
  }
}

// The plan stores each point's depth curvature (from the ideal process), so the exact search asks 3 wheel poses per
// point instead of 4 (FlankDeviation::at). Truth: the poses counted at the process, against the 4 the search without
// the curvature asks (simulate_topology on the same points); the deviations agree as above.
TEST(TopologyPlan, AsksThreeWheelPosesPerPointInsteadOfFour) {
  const auto model = test::random_machine(1.0, 11);
  const grinding::MachineProcess process(model, test::kDatumZ);
  const test::CountingPoses with_plan(process), without(process);
  auto o = plan_options();
  o.threads = 2;
  const grinding::TopologyPlan plan(test::paper_setup(), o);
  const double points = static_cast<double>(plan.points());
  const auto planned = plan.simulate(with_plan, 2);
  const auto plain = grinding::simulate_topology(test::paper_setup(), without, o);
  const double per_point_plan = static_cast<double>(with_plan.poses.load()) / points;
  const double per_point_plain = static_cast<double>(without.poses.load()) / points;
  std::printf("wheel poses per point: %.3f with the plan's curvature, %.3f without\n", per_point_plan, per_point_plain);
  EXPECT_LT(per_point_plan, 3.05);
  EXPECT_GE(per_point_plain, 4.0);
  EXPECT_LE(largest_difference_um(planned, plain), 1e-6);
}
