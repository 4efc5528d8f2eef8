#include "effects/effects_process.hpp"

#include "machine/chain.hpp"

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

machine::Vector6d EffectsProcess::error_twist_w(const grinding::PathPoint& pp) const {
  return machine::pose_error_twist(actual_wMg(pp) * machine::ideal_wMg(pp.q).inverse());
}

double EffectsProcess::wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const {
  double r = inner_.wheel_radius_error_mm(v, commanded(pp));
  for (const Effect* e : effects_) r += e->wheel_radius_error_mm(v, pp);
  return r;
}

} // namespace geartopo::effects
