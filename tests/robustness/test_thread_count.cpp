// Simulation results do not depend on the thread count: SimulationOptions::threads = 1, 2 and 4 give bit-identical
// deviations (grid, traces, dense grid) for every tooth and flank, exact and linear (src/grinding/parallel.hpp: each
// task writes its own slot).
#include "robustness_support.hpp"

#include "geartopo/grinding/topology.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

using namespace geartopo;
using namespace geartopo::robustness;

namespace {

// Every number of a simulation, as bits (so that -0.0 ≠ 0.0 and NaN patterns count too).
std::vector<std::uint64_t> bits(const std::vector<grinding::FlankTopology>& topo) {
  std::vector<std::uint64_t> out;
  auto put = [&](double v) { out.push_back(std::bit_cast<std::uint64_t>(v)); };
  for (const auto& ft : topo) {
    out.push_back(static_cast<std::uint64_t>(ft.tooth));
    out.push_back(static_cast<std::uint64_t>(ft.flank));
    for (const auto* grid : {&ft.grid, &ft.dense})
      for (const auto& p : *grid) {
        out.push_back(static_cast<std::uint64_t>(p.row * 100000 + p.col));
        put(p.roll_length_mm), put(p.diameter_mm), put(p.z_mm), put(p.deviation_um);
      }
    for (const auto* trace : {&ft.profile, &ft.helix})
      for (const auto& p : *trace) put(p.roll_length_mm), put(p.diameter_mm), put(p.z_mm), put(p.deviation_um);
  }
  return out;
}

class ThreadCount : public ::testing::TestWithParam<grinding::Method> {};

} // namespace

TEST_P(ThreadCount, DeviationsAreBitIdenticalFor1And2And4Threads) {
  const auto& d = default_scene();
  grinding::SimulationOptions o;
  o.method = GetParam();
  o.profile_points = 5; // every kind of output, few points each: the suite also runs under ASan at -O1
  o.helix_points = 6;
  o.dense_rows = 3;
  o.dense_cols = 4;
  // All 35 teeth (70 flanks, more tasks than threads, so the schedule differs between runs).
  std::vector<std::vector<std::uint64_t>> results;
  for (int threads : {1, 2, 4}) {
    o.threads = threads;
    results.push_back(bits(grinding::simulate_topology(d.setup, d.process(), o)));
  }
  ASSERT_EQ(results[0].size(), results[1].size());
  ASSERT_EQ(results[0].size(), results[2].size());
  size_t differ_2 = 0, differ_4 = 0;
  for (size_t i = 0; i < results[0].size(); ++i) {
    differ_2 += results[0][i] != results[1][i];
    differ_4 += results[0][i] != results[2][i];
  }
  EXPECT_EQ(differ_2, 0u) << "threads 1 vs 2";
  EXPECT_EQ(differ_4, 0u) << "threads 1 vs 4";
  // And the default (0 = all hardware threads) agrees too.
  o.threads = 0;
  EXPECT_EQ(bits(grinding::simulate_topology(d.setup, d.process(), o)), results[0]);
}

INSTANTIATE_TEST_SUITE_P(Methods, ThreadCount, ::testing::Values(grinding::Method::Exact, grinding::Method::Linear),
                         [](const auto& info) { return info.param == grinding::Method::Exact ? "Exact" : "Linear"; });
