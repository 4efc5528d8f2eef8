#include "geartopo/effects/effects_process.hpp"

#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/chain_kinematics.hpp"
#include "geartopo/machine/datum_shift.hpp"
#include "geartopo/machine/jacobian.hpp"

#include <cmath>
#include <numbers>

namespace geartopo::effects {

machine::Vector5d chain_offsets(const machine::KinematicChain& chain, const machine::Vector5d& by_role) {
  machine::Vector5d out = machine::Vector5d::Zero();
  // Every body frame is parallel at home and every linear axis runs along ±x, ±y or ±z, one per direction
  // (kinematic_chain.hpp): the role of a slide is its direction. The offset is a motion of that role's setting
  // coordinate (x, y, z, α, γ), so an axis that counts the other way takes it negated: θ = f·q as the inverse
  // kinematics orients it (KinematicChain::solve), f = ±1 by the axis' direction, and for a slide or the swivel by its
  // side (a workpiece-side axis moves the gear, the wheel relative to it the other way); the spindle's θ_C = ±γ.
  // A lag −T·dθ/dt is then −T·f·dγ/dt = f·(−T·dγ/dt) on a spindle about −z as about +z. f = +1 on every axis of the
  // three presets except the CAFXZY's A table (A = −α), which no library effect offsets.
  for (const machine::Joint& j : chain.joints()) {
    const int slot = static_cast<int>(j.slot);
    const bool spindle = j.kind == machine::AxisKind::Rotary && j.slot == machine::Axis::C;
    const double f = spindle ? j.sign : (j.workpiece_side ? -1.0 : 1.0) * j.sign;
    out(slot) = f * (j.kind == machine::AxisKind::Linear ? by_role(j.dir) : by_role(slot));
  }
  return out;
}

machine::Vector5d EffectsProcess::offset(const grinding::PathPoint& pp) const {
  machine::Vector5d o = machine::Vector5d::Zero();
  for (const Effect* e : effects_) o += e->command_offset(pp);
  return chain_ == nullptr ? o : chain_offsets(*chain_, o);
}

grinding::PathPoint EffectsProcess::commanded(const grinding::PathPoint& pp, const machine::Vector5d& o) const {
  grinding::PathPoint c = pp;
  if (chain_ == nullptr) {
    c.q = machine::AxisPose::from_vector(pp.q.vector() + o);
    return c;
  }
  // θ(q) + δθ back into the setting (gear coordinates: the chain's z less the datum face), the command's own turn kept
  // (as compensation::ChainAxes::corrected_setting).
  machine::AxisPose q = pp.q;
  q.z += datum_face_z_mm_;
  c.q = chain_->setting(machine::AxisValues{chain_->axes(q).v + o});
  c.q.z -= datum_face_z_mm_;
  c.q.c = pp.q.c + std::remainder(c.q.c - pp.q.c, 2.0 * std::numbers::pi);
  return c;
}

machine::Pose EffectsProcess::actual_wMg(const grinding::PathPoint& pp) const {
  machine::Pose wMg = inner_.actual_wMg(commanded(pp, offset(pp)));
  for (const Effect* e : effects_) wMg = e->table_in_gear(pp) * wMg;
  return wMg;
}

// First order throughout, like the inner process's own twist: the inner error at the commanded pose, the ideal
// pose's change from the command offsets (J_twistw_q, as CompensatedProcess adds its corrections; on another chain its
// J_twistw_theta, moved to the datum as ChainProcess moves its twist), and the table's mounting errors, which act in w
// (they multiply wMg from the left).
machine::Vector6d EffectsProcess::error_twist_w(const grinding::PathPoint& pp) const {
  const machine::Vector5d o = offset(pp);
  const grinding::PathPoint c = commanded(pp, o);
  machine::Vector6d twist = inner_.error_twist_w(c);
  if (chain_ == nullptr) {
    twist += machine::J_twistw_q(pp.q) * (c.q.vector() - pp.q.vector());
  } else {
    machine::AxisPose q = pp.q;
    q.z += datum_face_z_mm_;
    machine::Matrix65 J = machine::J_twistw_theta(*chain_, chain_->axes(q)); // 6×5
    machine::twists_at_datum(J, datum_face_z_mm_);
    twist += J * o;
  }
  for (const Effect* e : effects_) twist += machine::pose_error_twist(e->table_in_gear(pp));
  return twist;
}

double EffectsProcess::wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const {
  double r = inner_.wheel_radius_error_mm(v, commanded(pp, offset(pp)));
  for (const Effect* e : effects_) r += e->wheel_radius_error_mm(v, pp);
  return r;
}

} // namespace geartopo::effects
