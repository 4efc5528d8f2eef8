// geartopo — changed error components as a pose error of the wheel (component_changes.hpp). Units: mm, rad.
#include "geartopo/effects/component_changes.hpp"

#include "geartopo/machine/first_order.hpp"

#include <Eigen/Geometry>

namespace geartopo::effects {

ComponentChanges::ComponentChanges(std::vector<machine::ComponentChange> changes) : changes_(std::move(changes)) {
  init_defaults();
  // The first-order twist J_twistw_e(q)·δe depends on q through the ideal frames (the C angle turns w): constant only
  // when nothing changes.
  constant_ = true;
  for (const auto& c : changes_) constant_ = constant_ && c.size == 0.0;
}

const std::vector<ParameterSpec>& ComponentChanges::parameters() const {
  static const std::vector<ParameterSpec> none;
  return none;
}

machine::Pose pose_of_error_twist(const machine::Vector6d& xi) {
  machine::Pose E = machine::Pose::Identity();
  const Eigen::Vector3d theta = xi.tail<3>();
  const double angle = theta.norm();
  if (angle > 0.0) E.linear() = Eigen::AngleAxisd(angle, theta / angle).toRotationMatrix();
  E.translation() = xi.head<3>();
  return E;
}

machine::Pose ComponentChanges::table_in_gear(const grinding::PathPoint& pp) const {
  machine::ErrorVector delta = machine::ErrorVector::Zero();
  for (const auto& c : changes_) delta(machine::index(c.component)) += c.at(pp.time_s, pp.q.c);
  if (delta.isZero(0.0)) return machine::Pose::Identity();
  return pose_of_error_twist(machine::twist_w_linear(delta, pp.q));
}

} // namespace geartopo::effects
