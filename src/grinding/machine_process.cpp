#include "geartopo/grinding/machine_process.hpp"

#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/first_order.hpp"
#include "geartopo/machine/machine_data.hpp"
#include "geartopo/machine/transforms.hpp"

#include <optional>

namespace geartopo::grinding {

namespace {

// One chain evaluator per thread keeps the process shareable between threads. Along a stroke only C and Z move, and
// the evaluator recomputes only their joints: the pose is most of the exact search's cost (docs/performance.md).
// Keyed by the model's id, so a model built where another was freed is never confused with it.
machine::Pose evaluate_chain(const machine::MachineModel& model, const machine::AxisPose& q) {
  thread_local std::optional<machine::ChainEvaluator> evaluator;
  if (!evaluator || evaluator->model_id() != model.id()) evaluator.emplace(model, q);
  return evaluator->actual_wMg(model, q);
}

} // namespace

machine::Pose MachineProcess::actual_wMg(const PathPoint& pp) const {
  // T(0, 0, −z₀)·cMg without the product: the translation's z less z₀.
  machine::Pose wMg = evaluate_chain(model_, machine_axes(pp));
  wMg.translation().z() -= z0_;
  return wMg;
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
