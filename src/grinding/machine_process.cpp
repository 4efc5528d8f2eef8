#include "grinding/machine_process.hpp"

#include "machine/chain.hpp"
#include "machine/first_order.hpp"
#include "machine/machine_data.hpp"
#include "machine/transforms.hpp"

namespace geartopo::grinding {

// A fresh workspace per call keeps the process shareable between threads; it costs a few kB of zeroing, small
// against the chain evaluation itself.
machine::Pose MachineProcess::actual_wMg(const PathPoint& pp) const {
  machine::MachineData data;
  return machine::translation(0.0, 0.0, -z0_) * machine::actual_wMg(model_, data, machine_axes(pp));
}

machine::Vector6d MachineProcess::error_twist_w(const PathPoint& pp) const {
  machine::MachineData data;
  const machine::Vector6d twist_c = machine::twist_linear(model_, data, machine_axes(pp)).w;
  return machine::adjoint(machine::translation(0.0, 0.0, -z0_)) * twist_c;
}

machine::Vector6d MachineProcess::exact_error_twist_w(const PathPoint& pp) const {
  machine::MachineData data;
  const machine::Vector6d twist_c = machine::exact_pose_error(model_, data, machine_axes(pp)).w;
  return machine::adjoint(machine::translation(0.0, 0.0, -z0_)) * twist_c;
}

} // namespace geartopo::grinding
