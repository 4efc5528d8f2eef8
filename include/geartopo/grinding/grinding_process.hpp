// geartopo — what actually happens at a point of the wheel path: the wheel's actual pose and the state of its
// surface. The machine's geometric errors provide the pose (machine model); physical effects (a later issue: thermal
// drift, wear, deflection, …) add to the pose, the wheel or time through the same interface, so the simulator never
// pastes patterns onto its output.
// Units: mm, rad.
#pragma once

#include "geartopo/grinding/wheel_path.hpp"
#include "geartopo/machine/twist.hpp"

namespace geartopo::grinding {

class GrindingProcess {
public:
  virtual ~GrindingProcess() = default;

  /// Actual wheel pose in the workpiece frame at path point pp (exact: no small-angle approximation).  wMg
  virtual machine::Pose actual_wMg(const PathPoint& pp) const = 0;

  /// First-order pose error twist (δp; δθ) in the workpiece frame w at pp, defined by
  /// wMg_actual ≈ (I + [δθ]× | δp) · wMg_ideal.  // 6×1, mm and rad
  virtual machine::Vector6d error_twist_w(const PathPoint& pp) const = 0;

  /// Change of the wheel radius at axial coordinate v (mm, radial; positive: the wheel is bigger and cuts deeper).
  /// The surface then moves along its normal by δR/√(1 + R′²) (FormWheel::normal_per_radial).
  virtual double wheel_radius_error_mm(double /*v*/, const PathPoint& /*pp*/) const { return 0.0; }

  /// False only when wheel_radius_error_mm is 0 everywhere, so that the exact search may skip it at each Newton step
  /// (a compensated process looks its corrections up for it). True unless a process says otherwise: a process that
  /// changes the wheel needs to do nothing.
  virtual bool changes_wheel_radius() const { return true; }
};

/// The ideal machine: the nominal chain, no errors. Useful as a reference and in tests.
class IdealProcess final : public GrindingProcess {
public:
  machine::Pose actual_wMg(const PathPoint& pp) const override;
  machine::Vector6d error_twist_w(const PathPoint&) const override { return machine::Vector6d::Zero(); }
  bool changes_wheel_radius() const override { return false; }
};

} // namespace geartopo::grinding
