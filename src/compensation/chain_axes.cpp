// geartopo — the axes a correction table is written in (chain_axes.hpp). Units: mm, rad.
#include "geartopo/compensation/chain_axes.hpp"

#include "geartopo/machine/chain_kinematics.hpp"
#include "geartopo/machine/datum_shift.hpp"
#include "geartopo/machine/jacobian.hpp"

#include <cmath>
#include <numbers>

namespace geartopo::compensation {
namespace {

/// q with z moved by dz (gear coordinates ↔ the chain's setting, whose z = 0 is its workpiece frame's origin).
machine::AxisPose shifted(machine::AxisPose q, double dz) {
  q.z += dz;
  return q;
}

} // namespace

machine::Vector5d ChainAxes::axes(const machine::AxisPose& q) const {
  if (is_setting()) return q.vector();
  return chain->axes(shifted(q, datum_face_z_mm)).v;
}

machine::AxisPose ChainAxes::corrected_setting(const machine::AxisPose& q, const machine::Vector5d& dtheta) const {
  if (is_setting()) return machine::AxisPose::from_vector(q.vector() + dtheta);
  machine::AxisPose c = shifted(chain->setting(machine::AxisValues{axes(q) + dtheta}), -datum_face_z_mm);
  // setting() gives γ in (−π, π]; the command's own turn is kept (C tables and effects see the commanded γ).
  c.c = q.c + std::remainder(c.c - q.c, 2.0 * std::numbers::pi);
  return c;
}

machine::Matrix65 ChainAxes::J_twistg(const machine::AxisPose& q) const {
  if (is_setting()) return machine::J_twistg_q(q);
  return machine::J_twistg_theta(*chain, machine::AxisValues{axes(q)});
}

machine::Matrix65 ChainAxes::J_twistw(const machine::AxisPose& q) const {
  if (is_setting()) return machine::J_twistw_q(q);
  // The chain's w has its origin datum_face_z_mm below the gear's, as in ChainProcess::error_twist_w.
  machine::Matrix65 J = machine::J_twistw_theta(*chain, machine::AxisValues{axes(q)});
  machine::twists_at_datum(J, datum_face_z_mm);
  return J;
}

bool ChainAxes::within_strokes(const machine::Vector5d& theta) const {
  return chain == nullptr || chain->within_strokes(machine::AxisValues{theta});
}

std::string ChainAxes::axis_name(int slot) const {
  const auto a = static_cast<machine::Axis>(slot);
  return std::string(chain == nullptr ? machine::axis_name(a) : chain->axis_name(a));
}

} // namespace geartopo::compensation
