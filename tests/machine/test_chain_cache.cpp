// geartopo tests — the cached chain evaluator (chain_evaluator.hpp: joints that did not move kept, the twist in one
// backward pass) against the uncached chain kept as the reference (chain_kinematics.hpp: every joint recomputed,
// the full 6×43 error Jacobian times e), on three layouts, at sequences of axis positions in which axes stand still,
// move one at a time, as along a stroke, and all at once, on a machine whose every motion component varies with its
// axis. Units: mm, rad.
#include "test_helpers.hpp"

#include "geartopo/machine/chain_evaluator.hpp"
#include "geartopo/machine/chain_kinematics.hpp"
#include "geartopo/machine/error_source.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <numbers>

namespace geartopo::machine {
namespace {

constexpr double kRad = std::numbers::pi / 180.0;

/// A layout no preset has (the radial slide under the table, moving along −x; the swivel's axis 120 mm above the
/// wheel centre), so that offsets, a negative direction and two workpiece-side joints are exercised.
const KinematicChain& cache_test_chain() {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  return make_chain({"CXFZAY",
                     {{"C", AxisKind::Rotary, z, Eigen::Vector3d::Zero(), std::nullopt},
                      {"X", AxisKind::Linear, -x, Eigen::Vector3d(0.0, 0.0, -40.0), Interval{0.0, 900.0}}},
                     {{"Z", AxisKind::Linear, z, Eigen::Vector3d::Zero(), Interval{0.0, 800.0}},
                      {"A", AxisKind::Rotary, x, Eigen::Vector3d::Zero(), Interval{-45 * kRad, 45 * kRad}},
                      {"Y", AxisKind::Linear, y, Eigen::Vector3d(0.0, 0.0, -120.0), Interval{-200.0, 200.0}}}});
}

/// Every motion component a function of its axis' position (a polynomial; the spindle's a periodic table), every
/// constant random, sizes 30 µm / 30 µrad.
MachineModel machine_varying_everywhere(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<ErrorSource> sources;
  for (int i = 0; i < kComponentCount; ++i) {
    const auto id = component_at(i);
    const ComponentInfo& c = info(id);
    const auto unit = c.quantity == Quantity::Angle ? "urad" : "um";
    if (c.position_dependent && c.axis == Axis::C) {
      std::vector<double> x, y;
      for (int k = 0; k <= 36; ++k) {
        x.push_back(2.0 * std::numbers::pi * k / 36);
        y.push_back(3e-5 * u(rng));
      }
      y.back() = y.front();
      sources.push_back(ErrorSource::table(id, CubicSpline(x, y, CubicSpline::Ends::Periodic), {}));
    } else if (c.position_dependent) {
      sources.push_back(ErrorSource::polynomial(id, {30.0 * u(rng), 0.05 * u(rng), 1e-4 * u(rng)}, unit,
                                                is_rotary(c.axis) ? "deg" : "mm"));
    } else {
      sources.push_back(ErrorSource::constant(id, 30.0 * u(rng), unit));
    }
  }
  return MachineModel(Strokes::skmc_1200w(), std::move(sources));
}

/// Axis positions in pose order: the previous ones with some moved — none, one, the spindle and one linear axis
/// (a stroke), or all — chosen by `step`.
AxisValues next_positions(const AxisValues& previous, int step, std::mt19937& rng) {
  const Vector5d fresh = test::random_pose(rng).vector();
  AxisValues theta = previous;
  switch (step % 5) {
  case 0: break;                                                      // nothing moved
  case 1: theta.v(step % kAxisCount) = fresh(step % kAxisCount); break; // one axis
  case 2:                                                             // a stroke: spindle and one linear axis
    theta[Axis::C] = fresh(4);
    theta.v(step % 3) = fresh(step % 3);
    break;
  default: theta.v = fresh; break;                                    // everything
  }
  return theta;
}

bool same_bits(const Pose& a, const Pose& b) { return std::memcmp(a.data(), b.data(), sizeof(double) * 16) == 0; }
bool same_bits(const Vector6d& a, const Vector6d& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * 6) == 0;
}

TEST(ChainCache, CachedEvaluatorIsTheUncachedChainAtRandomPositionsAndErrors) {
  std::mt19937 rng(42);
  const MachineModel model = machine_varying_everywhere(rng);
  const MachineModel other = machine_varying_everywhere(rng);
  for (const KinematicChain* chain : {&cfxzay(), chain_preset("CAFXZY"), &cache_test_chain()}) {
    ChainData data;
    AxisValues theta;
    theta.v = test::random_pose(rng).vector();
    for (int step = 0; step < 400; ++step) {
      theta = next_positions(theta, step, rng);
      // Now and then the same scratch serves another model first: it must rebind, not mix the two.
      if (step % 37 == 0) {
        AxisValues elsewhere;
        elsewhere.v = test::random_pose(rng).vector();
        (void)actual_wMg(*chain, other, data, elsewhere);
        (void)twist_w_linear(*chain, other, data, elsewhere);
      }
      ErrorVector e;
      errors_at(model, theta, e);
      const Pose reference = actual_wMg(*chain, e, theta);
      Matrix6E J_twistw_e, J_twistg_e;
      error_jacobians(*chain, theta, J_twistw_e, J_twistg_e);
      const Vector6d twist_reference = J_twistw_e * e;

      const Pose cached = actual_wMg(*chain, model, data, theta);
      const Vector6d twist = twist_w_linear(*chain, model, data, theta);
      SCOPED_TRACE(chain->name() + ", step " + std::to_string(step));
      // 1e-12 mm at the wheel centre; rotation entries × a 1000 mm lever; the twist in mm and rad.
      EXPECT_LT((cached.translation() - reference.translation()).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT(1000.0 * (cached.linear() - reference.linear()).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((twist - twist_reference).cwiseAbs().maxCoeff(), 1e-12);
      // Not a model checked against itself only: the errors are there (tens of µm at the wheel).
      EXPECT_GT((twist_reference.head<3>()).norm(), 1e-3);
      // Whatever the scratch held before, the same bits as a fresh one: results identical at any thread count.
      ChainData fresh;
      EXPECT_TRUE(same_bits(cached, actual_wMg(*chain, model, fresh, theta)));
      EXPECT_TRUE(same_bits(twist, twist_w_linear(*chain, model, fresh, theta)));
    }
  }
}

} // namespace
} // namespace geartopo::machine
