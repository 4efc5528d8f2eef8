#include "geartopo/grinding/machine_process.hpp"

#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/first_order.hpp"
#include "geartopo/machine/machine_data.hpp"
#include "geartopo/machine/transforms.hpp"

namespace geartopo::grinding {

// A fresh workspace per call keeps the process shareable between threads; it costs a few kB of zeroing, small
// against the chain evaluation itself.
machine::Pose MachineProcess::actual_wMg(const PathPoint& pp) const {
  machine::MachineData data;
  return machine::translation(0.0, 0.0, -z0_) * machine::actual_wMg(model_, data, machine_axes(pp));
}

machine::Vector6d MachineProcess::error_twist_w(const PathPoint& pp) const {
  const machine::AxisPose q = machine_axes(pp);
  machine::ErrorVector e;
  model_.errors_at(q, e);
  // The datum shift T(0, 0, −z₀) is a pure translation along the C axis: it moves the twist's point of reference.
  machine::Vector6d twist = machine::twist_w_linear(e, q);
  twist.head<3>() += Eigen::Vector3d(0.0, 0.0, -z0_).cross(twist.tail<3>());
  return twist;
}

machine::Vector6d MachineProcess::exact_error_twist_w(const PathPoint& pp) const {
  machine::MachineData data;
  const machine::Vector6d twist_c = machine::exact_pose_error(model_, data, machine_axes(pp)).w;
  return machine::adjoint(machine::translation(0.0, 0.0, -z0_)) * twist_c;
}

} // namespace geartopo::grinding
