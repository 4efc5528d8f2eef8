// geartopo tests — repeated evaluations with a MachineData workspace allocate nothing (heap counted through
// replaced global operator new). Units: mm, rad.
#include "test_helpers.hpp"

#include "geartopo/machine/chain_evaluator.hpp"
#include "geartopo/machine/error_table.hpp"
#include "geartopo/machine/first_order.hpp"
#include "geartopo/machine/jacobian.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long> g_allocations{0};
}

// The replacements pair operator new with malloc and operator delete with free, so GCC's -Wmismatched-new-delete
// (reported at -O1 in the sanitizer build) is a false positive here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return ::operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace geartopo::machine {
namespace {

TEST(NoAllocation, RepeatedEvaluationsUseOnlyTheWorkspace) {
  std::vector<ErrorSource> s = load_error_tables(test::data_path("x_axis.csv"));
  for (ErrorSource& c : load_error_tables(test::data_path("c_axis.csv"))) s.push_back(std::move(c));
  s.push_back(ErrorSource::polynomial(ComponentId::delta_zz, {2.0, 0.01}, "um", "mm"));
  s.push_back(ErrorSource::constant(ComponentId::E_XOC, 12.0, "um"));
  const MachineModel model(Strokes::skmc_1200w(), std::move(s));
  MachineData data;
  std::mt19937 rng(41);
  std::vector<AxisPose> poses;
  for (int i = 0; i < 200; ++i) {
    AxisPose q = test::random_pose(rng);
    q.x = std::min(q.x, 900.0);
    poses.push_back(q);
  }
  const KinematicChain& cfxzay_chain = cfxzay(), &cafxzy = *chain_preset("CAFXZY"); // made before counting
  ChainData chain_data;
  double sink = 0.0;
  const long before = g_allocations.load();
  for (const AxisPose& q : poses) {
    sink += actual_wMg(model, data, q).translation().x();
    sink += exact_pose_error(model, data, q).w(0);
    sink += twist_linear(model, data, q).g(1);
    model.errors_at(q, data.e);
    sink += twist_w_linear(data.e, q)(2);
    actual_jacobians(model, data, q);
    sink += data.J_twistg_q(0, 4) + J_twistg_q(q)(1, 4) + J_twistw_q(q)(2, 3);
    // The cached chain evaluator (ChainProcess), rebinding to another chain at each pose.
    for (const KinematicChain* chain : {&cfxzay_chain, &cafxzy}) {
      const AxisValues theta{q.vector()};
      sink += actual_wMg(*chain, model, chain_data, theta).translation().y() +
              twist_w_linear(*chain, model, chain_data, theta)(4);
    }
  }
  const long during = g_allocations.load() - before;
  EXPECT_EQ(during, 0) << "heap allocations during evaluation";
  EXPECT_TRUE(std::isfinite(sink));
  // The counter does count: building a model allocates.
  const long b2 = g_allocations.load();
  const MachineModel other(Strokes::skmc_1200w());
  EXPECT_GT(g_allocations.load() - b2, 0);
}

} // namespace
} // namespace geartopo::machine
