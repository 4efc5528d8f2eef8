// geartopo — the grinding process of a machine whose kinematic chain is described as data (machine/kinematic_chain.hpp):
// at each path point the chain's inverse kinematics gives its own axis positions θ for the commanded wheel–gear
// setting, the model's error components are evaluated at θ (its tables are functions of the chain's axes), and the
// chain's exact joints give the wheel pose; the first-order twist is the chain's error Jacobian times e, summed joint
// by joint in one backward pass. Both through machine::ChainData (chain_evaluator.hpp), one per thread, which keeps
// the joints that did not move since the thread's last point (along a stroke all but the spindle and the stroke
// axes): per point as fast as MachineProcess on the CFXZAY (docs/performance.md, ChainPoint), the same bits at any
// thread count.
//
// As MachineProcess: the chain's workpiece frame has its origin where the chain puts the wheel at the setting's
// z = 0; the gear's datum face sits at z = z₀, so the chain is asked for z + z₀ and poses come back through Tz(−z₀).
// On the CFXZAY this is MachineProcess's model (tests/machine: the chain as data equals the compiled-in chain), which
// the workbench keeps for it (its numbers frozen bit for bit).
// Units: mm, rad.
#pragma once

#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/machine/kinematic_chain.hpp"
#include "geartopo/machine/machine_model.hpp"

namespace geartopo::grinding {

class ChainProcess final : public GrindingProcess {
public:
  /// `chain` is kept by make_chain for the program's life; `model` must outlive the process.
  ChainProcess(const machine::KinematicChain& chain, const machine::MachineModel& model, double datum_face_z_mm)
      : chain_(chain), model_(model), z0_(datum_face_z_mm) {}

  /// The chain's axis positions for a path point (its setting with z shifted by the datum face), mm and rad.
  machine::AxisValues machine_axes(const PathPoint& pp) const;

  machine::Pose actual_wMg(const PathPoint& pp) const override;
  machine::Vector6d error_twist_w(const PathPoint& pp) const override;
  bool changes_wheel_radius() const override { return false; } ///< geometric errors move the wheel, never resize it

  /// Throws std::runtime_error at the first point of the path (every stroke sampled each `step_mm`, ends included)
  /// the chain cannot make: "space 3, Z = 12.500 mm: Y = 612.300 mm is outside its stroke [-500, 500] mm", or the
  /// linear axes singular there (|det| < 1e-3, kinematic_chain.hpp).
  void check_path(const WheelPath& path, double step_mm = 1.0) const;

  const machine::KinematicChain& chain() const { return chain_; }
  const machine::MachineModel& model() const { return model_; }
  double datum_face_z_mm() const { return z0_; }

private:
  const machine::KinematicChain& chain_;
  const machine::MachineModel& model_;
  double z0_;
};

} // namespace geartopo::grinding
