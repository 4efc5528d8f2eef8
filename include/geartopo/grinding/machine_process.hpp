// geartopo — the grinding process of a machine with geometric errors: the machine model's exact chain gives the
// wheel pose, its first-order model the error twist.
//
// The machine's own workpiece frame (the C table, "c") has its origin where the chain puts the wheel at Z = 0; the
// gear's datum face sits at machine Z = z₀ (scene: machine.datum_face_z_mm). Path commands are in gear coordinates,
// so the machine sees Z + z₀, and poses come back through wMc = Tz(−z₀); twists through Ad(wMc).
// Units: mm, rad.
#pragma once

#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/machine/machine_model.hpp"

namespace geartopo::grinding {

class MachineProcess final : public GrindingProcess {
public:
  MachineProcess(const machine::MachineModel& model, double datum_face_z_mm)
      : model_(model), z0_(datum_face_z_mm) {}

  /// The axes the machine actually receives for a path point (Z shifted by the datum face position).
  machine::AxisPose machine_axes(const PathPoint& pp) const {
    machine::AxisPose q = pp.q;
    q.z += z0_;
    return q;
  }

  machine::Pose actual_wMg(const PathPoint& pp) const override;
  machine::Vector6d error_twist_w(const PathPoint& pp) const override;
  bool changes_wheel_radius() const override { return false; } ///< geometric errors move the wheel, never resize it
  /// The exact pose error twist in w (for comparisons with the first-order model).  // 6×1
  machine::Vector6d exact_error_twist_w(const PathPoint& pp) const;

  const machine::MachineModel& model() const { return model_; }
  double datum_face_z_mm() const { return z0_; }

private:
  const machine::MachineModel& model_;
  double z0_;
};

} // namespace geartopo::grinding
