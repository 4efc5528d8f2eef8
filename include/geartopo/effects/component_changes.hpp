// geartopo — error components that changed since the map was measured, acting on the wheel pose
// (machine/component_change.hpp; scene key `machine_changes`, docs/scene-format.md).
//
// Not a plug-in of the registry: its "parameters" are the changes themselves (component, law, size), which the scene
// lists and diagnosis identifies among the chain's 43 components (docs/diagnosis.md, "Beyond the library"). It acts
// through the simulator like an effect: the changed components' first-order pose error ξ_w = J_twistw_e(q)·δe(t)
// (machine/first_order.hpp), evaluated at the commanded pose and the path point's time, multiplies the wheel pose
// from the left (EffectsProcess: table_in_gear · wMg). On another chain than the CFXZAY its own J_twistw_e at its axes
// θ(q) (machine/chain_kinematics.hpp), moved to the datum as grinding::ChainProcess::error_twist_w does.
// Units: mm, rad inside.
#pragma once

#include "geartopo/effects/effect.hpp"
#include "geartopo/machine/component_change.hpp"
#include "geartopo/machine/kinematic_chain.hpp"

#include <vector>

namespace geartopo::effects {

class ComponentChanges final : public Effect {
public:
  /// `chain`: the scene's (null: the CFXZAY), the gear's datum face at its z = datum_face_z_mm.
  explicit ComponentChanges(std::vector<machine::ComponentChange> changes, const machine::KinematicChain* chain = nullptr,
                            double datum_face_z_mm = 0.0);
  std::string_view type() const override { return "machine_changes"; }
  std::string_view explanation() const override {
    return "error components of the machine changed since its map was measured";
  }
  const std::vector<ParameterSpec>& parameters() const override;
  std::unique_ptr<Effect> clone() const override { return std::make_unique<ComponentChanges>(*this); }
  /// exp(ξ_w) with ξ_w = J_twistw_e(pp.q)·δe(pp.time_s): translation ξ_w's, rotation the rotation vector's, so that
  /// machine::pose_error_twist gives ξ_w back exactly.  wMc
  machine::Pose table_in_gear(const grinding::PathPoint& pp) const override;
  bool table_in_gear_is_constant() const override { return constant_; }
  const std::vector<machine::ComponentChange>& changes() const { return changes_; }

private:
  std::vector<machine::ComponentChange> changes_;
  const machine::KinematicChain* chain_ = nullptr; ///< null or the CFXZAY: machine::twist_w_linear
  double datum_face_z_mm_ = 0.0;
  bool constant_ = false; ///< every change zero: J_twistw_e(q)·δe depends on q (the C angle turns w) otherwise
};

/// The pose of a pose-error twist (translation; rotation vector), the inverse of machine::pose_error_twist.
machine::Pose pose_of_error_twist(const machine::Vector6d& xi);

} // namespace geartopo::effects
