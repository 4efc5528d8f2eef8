// geartopo — changed error components as a pose error of the wheel (component_changes.hpp). Units: mm, rad.
#include "geartopo/effects/component_changes.hpp"

#include "geartopo/machine/chain_kinematics.hpp"
#include "geartopo/machine/datum_shift.hpp"
#include "geartopo/machine/first_order.hpp"

#include <Eigen/Geometry>

namespace geartopo::effects {

ComponentChanges::ComponentChanges(std::vector<machine::ComponentChange> changes, const machine::KinematicChain* chain,
                                   double datum_face_z_mm)
    : changes_(std::move(changes)), chain_(chain != nullptr && !chain->is_setting_chain() ? chain : nullptr),
      datum_face_z_mm_(datum_face_z_mm) {
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
  // At the machine's axes, z + z₀, the twist moved back to the datum: what the same errors in the map grind.
  machine::AxisPose q = pp.q;
  q.z += datum_face_z_mm_;
  if (chain_ == nullptr)
    return pose_of_error_twist(machine::twist_at_datum(machine::twist_w_linear(delta, q), datum_face_z_mm_));
  machine::Matrix6E J_twistw_e, J_twistg_e;
  machine::error_jacobians(*chain_, chain_->axes(q), J_twistw_e, J_twistg_e);
  return pose_of_error_twist(machine::twist_at_datum(J_twistw_e * delta, datum_face_z_mm_));
}

} // namespace geartopo::effects
