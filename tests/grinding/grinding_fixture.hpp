// Shared set-up for the grinding tests: the seed paper's gear on a 350 mm wheel, built once per test binary.
#pragma once

#include "../gears/gear_fixtures.hpp"
#include "geartopo/grinding/grinding_setup.hpp"
#include "geartopo/grinding/machine_process.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/machine/error_source.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <memory>
#include <random>

namespace geartopo::test {

inline const grinding::GrindingSetup& paper_setup() {
  static const grinding::GrindingSetup setup(paper_gear(), {350.0, 0.0}, {});
  return setup;
}

/// Machine Z of the datum face used by the tests: inside the default Z stroke [0, 800] for the whole path.
inline constexpr double kDatumZ = 300.0;

/// A machine with the given error sources and the paper's strokes.
inline machine::MachineModel machine_with(std::vector<machine::ErrorSource> sources) {
  return machine::MachineModel(machine::Strokes::skmc_1200w(), std::move(sources));
}

/// Random errors on all 43 components, at most `scale` × 50 µm / 100 µrad: the motion components vary linearly along
/// their axis (except δ_xc and the Y axis), the others are constants. The same draw for the same seed.
inline machine::MachineModel random_machine(double scale, unsigned seed) {
  using machine::ErrorSource;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<ErrorSource> sources;
  for (int i = 0; i < machine::kComponentCount; ++i) {
    const auto id = machine::component_at(i);
    const bool angle = machine::info(id).quantity == machine::Quantity::Angle;
    const double amp = scale * (angle ? 100.0 : 50.0);
    const auto unit = angle ? "urad" : "um";
    const bool varies = i < machine::kMotionComponentCount && id != machine::ComponentId::delta_xc && i / 6 != 4;
    if (varies) {
      const bool rotary = i / 6 == 3;
      const double span = rotary ? 90.0 : 900.0; // deg or mm
      sources.push_back(
          ErrorSource::polynomial(id, {0.5 * amp * u(rng), 0.5 * amp * u(rng) / span}, unit, rotary ? "deg" : "mm"));
    } else {
      sources.push_back(ErrorSource::constant(id, 0.5 * amp * u(rng), unit));
    }
  }
  return machine_with(sources);
}

/// A process whose wheel pose is the ideal one changed by a fixed rule, to test invariances and searches.
class ModifiedProcess final : public grinding::GrindingProcess {
public:
  explicit ModifiedProcess(std::function<machine::Pose(const grinding::PathPoint&)> f) : f_(std::move(f)) {}
  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override { return f_(pp); }
  machine::Vector6d error_twist_w(const grinding::PathPoint&) const override { return machine::Vector6d::Zero(); }

private:
  std::function<machine::Pose(const grinding::PathPoint&)> f_;
};

/// The same process, saying it may change the wheel's radius (by zero, so the same function f): the exact search's
/// Newton (FlankDeviation::entry_depth) then runs until a step is below 1e-12 mm — to rounding, the stopping rule
/// before the bounded early stop — to check that stop against.
class NewtonToRounding final : public grinding::GrindingProcess {
public:
  explicit NewtonToRounding(const grinding::GrindingProcess& inner) : inner_(inner) {}
  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override { return inner_.actual_wMg(pp); }
  machine::Vector6d error_twist_w(const grinding::PathPoint& pp) const override { return inner_.error_twist_w(pp); }
  double wheel_radius_error_mm(double, const grinding::PathPoint&) const override { return 0.0; }
  bool changes_wheel_radius() const override { return true; }

private:
  const grinding::GrindingProcess& inner_;
};

/// The same process, counting the wheel poses a search asks for (from any thread).
class CountingPoses final : public grinding::GrindingProcess {
public:
  explicit CountingPoses(const grinding::GrindingProcess& inner) : inner_(inner) {}
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

inline std::vector<grinding::FlankTopology> simulate(const grinding::GrindingProcess& p, grinding::Method m,
                                                     std::vector<int> teeth = {1, 18}) {
  grinding::SimulationOptions o;
  o.method = m;
  o.teeth = std::move(teeth);
  o.profile_points = 20;
  o.helix_points = 20;
  return grinding::simulate_topology(paper_setup(), p, o);
}

} // namespace geartopo::test
