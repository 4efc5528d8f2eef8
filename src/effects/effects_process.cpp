#include "geartopo/effects/effects_process.hpp"

#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/jacobian.hpp"

namespace geartopo::effects {

grinding::PathPoint EffectsProcess::commanded(const grinding::PathPoint& pp) const {
  machine::Vector5d offset = machine::Vector5d::Zero();
  for (const Effect* e : effects_) offset += e->command_offset(pp);
  grinding::PathPoint c = pp;
  c.q = machine::AxisPose::from_vector(pp.q.vector() + offset);
  return c;
}

machine::Pose EffectsProcess::actual_wMg(const grinding::PathPoint& pp) const {
  machine::Pose wMg = inner_.actual_wMg(commanded(pp));
  for (const Effect* e : effects_) wMg = e->table_in_gear(pp) * wMg;
  return wMg;
}

// First order throughout, like the inner process's own twist: the inner error at the commanded pose, the ideal
// pose's change from the command offsets (J_twistw_q, as CompensatedProcess adds its corrections), and the table's
// mounting errors, which act in w (they multiply wMg from the left).
machine::Vector6d EffectsProcess::error_twist_w(const grinding::PathPoint& pp) const {
  const grinding::PathPoint c = commanded(pp);
  machine::Vector6d twist = inner_.error_twist_w(c) + machine::J_twistw_q(pp.q) * (c.q.vector() - pp.q.vector());
  for (const Effect* e : effects_) twist += machine::pose_error_twist(e->table_in_gear(pp));
  return twist;
}

double EffectsProcess::wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const {
  double r = inner_.wheel_radius_error_mm(v, commanded(pp));
  for (const Effect* e : effects_) r += e->wheel_radius_error_mm(v, pp);
  return r;
}

} // namespace geartopo::effects
