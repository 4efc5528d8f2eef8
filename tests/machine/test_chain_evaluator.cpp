// ChainEvaluator (the exact chain recomputing only the joints whose axis moved) against the plain exact chain,
// machine::actual_wMg with a fresh workspace: the same bits at every pose of a sequence in which axes stand still,
// move one at a time and all at once, on a machine with position-dependent errors on every axis.
#include "test_helpers.hpp"

#include "geartopo/machine/error_source.hpp"
#include "geartopo/machine/machine_data.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace geartopo::machine::test {
namespace {

/// Every motion component a polynomial in its axis' position, the constants random: each joint depends on its axis.
MachineModel machine_varying_on_every_axis(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<ErrorSource> sources;
  for (int i = 0; i < kComponentCount; ++i) {
    const auto id = component_at(i);
    const ComponentInfo& c = info(id);
    const bool angle = c.quantity == Quantity::Angle;
    const auto unit = angle ? "urad" : "um";
    if (c.position_dependent && c.axis != Axis::C)
      sources.push_back(ErrorSource::polynomial(id, {30.0 * u(rng), 0.05 * u(rng), 1e-4 * u(rng)}, unit,
                                                is_rotary(c.axis) ? "deg" : "mm"));
    else
      sources.push_back(ErrorSource::constant(id, 30.0 * u(rng), unit));
  }
  return MachineModel(Strokes::skmc_1200w(), std::move(sources));
}

/// A spline column over [lo, hi] on n evenly spaced knots (periodic when asked), values of size `scale`.
ErrorSource table_column(ComponentId id, double lo, double hi, int n, double scale, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> x, y;
  for (int i = 0; i < n; ++i) {
    x.push_back(lo + (hi - lo) * i / (n - 1));
    y.push_back(scale * u(rng));
  }
  const bool periodic = info(id).axis == Axis::C;
  if (periodic) y.back() = y.front();
  return ErrorSource::table(id, CubicSpline(x, y, periodic ? CubicSpline::Ends::Periodic : CubicSpline::Ends::NotAKnot), {});
}

} // namespace

TEST(MachineModel, OneSearchPerSharedTableGivesEachComponentsOwnValue) {
  // axis_errors_at and errors_at search the knots once for the columns of one table (CubicSpline::value_at). Truth:
  // each component's own ErrorSource::value at its axis' position (its own search). Every axis has its six columns on
  // one table except X, whose δ_xx column has knots of its own and whose ε_zx is a polynomial: three kinds of entry.
  std::mt19937 rng(17);
  std::vector<ErrorSource> sources;
  for (int i = 0; i < kComponentCount; ++i) {
    const auto id = component_at(i);
    const ComponentInfo& c = info(id);
    const double scale = c.quantity == Quantity::Angle ? 5e-5 : 3e-2;
    if (!c.position_dependent) continue;
    if (id == ComponentId::epsilon_zx) {
      sources.push_back(ErrorSource::polynomial(id, {4.0, 0.02}, "urad", "mm"));
      continue;
    }
    switch (c.axis) {
    case Axis::X: sources.push_back(table_column(id, 0.0, 900.0, id == ComponentId::delta_xx ? 10 : 19, scale, rng)); break;
    case Axis::Y: sources.push_back(table_column(id, -200.0, 200.0, 17, scale, rng)); break;
    case Axis::Z: sources.push_back(table_column(id, 0.0, 800.0, 33, scale, rng)); break;
    case Axis::A: sources.push_back(table_column(id, -0.8, 0.8, 19, scale, rng)); break;
    case Axis::C: sources.push_back(table_column(id, 0.0, 2.0 * std::numbers::pi, 73, scale, rng)); break;
    }
  }
  const MachineModel model(Strokes::skmc_1200w(), std::move(sources));
  for (int k = 0; k < 200; ++k) {
    const AxisPose q = random_pose(rng);
    ErrorVector e = ErrorVector::Constant(std::nan(""));
    model.errors_at(q, e);
    for (int i = 0; i < kComponentCount; ++i) {
      const ErrorSource& s = model.source(component_at(i));
      ASSERT_EQ(e(i), s.value(q[info(s.id()).axis])) << info(s.id()).name << " at pose " << k;
    }
  }
}

TEST(ChainEvaluator, GivesTheExactChainBitForBitWhateverMoves) {
  std::mt19937 rng(31);
  const MachineModel model = machine_varying_on_every_axis(rng);
  AxisPose q = random_pose(rng);
  ChainEvaluator evaluator(model, q);
  std::uniform_int_distribution<int> which(0, 6);
  for (int k = 0; k < 400; ++k) {
    const AxisPose fresh = random_pose(rng);
    const int w = which(rng); // 0..4: that axis moves; 5: only Z and C (a stroke); 6: all
    if (w < 5) q[kAxes[static_cast<size_t>(w)]] = fresh[kAxes[static_cast<size_t>(w)]];
    if (w == 5) q.z = fresh.z, q.c = fresh.c;
    if (w == 6) q = fresh;
    MachineData data;
    const Pose expected = actual_wMg(model, data, q);
    const Pose got = evaluator.actual_wMg(model, q);
    ASSERT_EQ(got.matrix(), expected.matrix()) << "pose " << k << ", case " << w;
  }
}

TEST(ChainEvaluator, ModelsHaveDistinctIdsAndCopiesShareThem) {
  std::mt19937 rng(5);
  const MachineModel a = machine_varying_on_every_axis(rng);
  const MachineModel b = machine_varying_on_every_axis(rng);
  const MachineModel a_copy = a; // NOLINT(performance-unnecessary-copy-initialization): the copy is the point
  EXPECT_NE(a.id(), b.id());
  EXPECT_EQ(a.id(), a_copy.id());
}

} // namespace geartopo::machine::test
