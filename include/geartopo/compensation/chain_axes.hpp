// geartopo — the axes a correction table is written in (docs/machine-model.md §9, docs/compensation.md): the scene's
// kinematic chain's own axes θ, in its pose order, for the gear's datum face at chain z = datum_face_z_mm. On the
// CFXZAY (or with no chain given) these are the setting's own coordinates q (x, y, z, α, γ: its inverse kinematics is
// the identity), and every function below is today's closed form exactly (machine/jacobian.hpp).
// Units: mm, rad.
#pragma once

#include "geartopo/machine/axis_pose.hpp"
#include "geartopo/machine/kinematic_chain.hpp"
#include "geartopo/machine/machine_data.hpp"

#include <string>

namespace geartopo::compensation {

struct ChainAxes {
  /// The chain whose axes a correction moves; null: the setting's coordinates (the CFXZAY's axes).
  const machine::KinematicChain* chain = nullptr;
  double datum_face_z_mm = 0.0; ///< where the gear's datum face sits along the chain's setting z (mm)

  /// True when the axes are the setting's own coordinates (no chain, or the CFXZAY).
  bool is_setting() const { return chain == nullptr || chain->is_setting_chain(); }

  /// The chain's axis positions θ for the setting q (gear coordinates: the datum face at z = 0).  5×1, mm and rad
  machine::Vector5d axes(const machine::AxisPose& q) const;
  /// The setting the chain makes at θ(q) + Δθ (gear coordinates; γ kept within π of q's).
  machine::AxisPose corrected_setting(const machine::AxisPose& q, const machine::Vector5d& dtheta) const;
  /// Body twist of the ideal wheel (in g) per unit of each axis at q (J_twistg_theta; J_twistg_q on the CFXZAY).  6×5
  machine::Matrix65 J_twistg(const machine::AxisPose& q) const;
  /// Spatial twist (in the gear's w, datum face at z = 0) per unit of each axis at q.  6×5
  machine::Matrix65 J_twistw(const machine::AxisPose& q) const;
  /// True when θ lies within the chain's strokes; always without a chain (compute_corrections checks the CFXZAY's
  /// commands against the machine model's strokes instead, as before).
  bool within_strokes(const machine::Vector5d& theta) const;
  /// The axis' name in pose slot `slot` ("X", "A"; the CFXZAY's letters without a chain).
  std::string axis_name(int slot) const;
};

} // namespace geartopo::compensation
