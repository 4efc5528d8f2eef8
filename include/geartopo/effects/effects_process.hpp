// geartopo — a grinding process with physical effects on top of another process (usually the machine's geometric
// error model). Commands get the effects' offsets before the machine sees them; the gear frame gets the effects'
// mounting errors; the wheel gets their radius changes. Units: mm, rad.
//
// The command offsets are the machine's axes': an effect names them in the CFXZAY's order (X, Y, Z, A, C: the slides
// along x — the centre distance —, y and z, the swivel, the spindle), and on another chain each goes to that chain's
// axis of the same role (chain_offsets: its slide along the same direction, its swivel, its spindle), the corrected
// command θ(q) + δθ turned back into the setting by the chain's forward kinematics and, to first order, through its
// axis Jacobian J_twistw_theta (docs/machine-model.md §9). On the CFXZAY (no chain) θ = q: today's q + δq exactly.
#pragma once

#include "geartopo/effects/effect.hpp"
#include "geartopo/grinding/grinding_process.hpp"
#include "geartopo/machine/kinematic_chain.hpp"

#include <memory>
#include <vector>

namespace geartopo::effects {

/// An offset given in the CFXZAY's order of roles (the slides along x, y and z, the swivel, the spindle: motions of
/// the setting's x, y, z, α, γ) in `chain`'s pose order: the slide along x to the chain's linear axis along x, and so
/// on, negated for an axis that counts against its role's coordinate (a spindle about −z: θ_C = −γ; a tool-side slide
/// along −x). The identity on the CFXZAY and the CXFZAY, and on the CAFXZY but for its A table (A = −α); on a chain
/// with a radial slide U, U's slot.
machine::Vector5d chain_offsets(const machine::KinematicChain& chain, const machine::Vector5d& by_role);

class EffectsProcess final : public grinding::GrindingProcess {
public:
  /// `effects` must be bound to the same set-up and outlive the process. `chain` (null or the CFXZAY: the setting's
  /// coordinates) is the machine whose axes the command offsets act on, the gear's datum face at its z =
  /// datum_face_z_mm; it must outlive the process (make_chain keeps every chain).
  EffectsProcess(const grinding::GrindingProcess& inner, std::vector<const Effect*> effects,
                 const machine::KinematicChain* chain = nullptr, double datum_face_z_mm = 0.0)
      : inner_(inner), effects_(std::move(effects)), chain_(own_axes(chain)), datum_face_z_mm_(datum_face_z_mm) {}
  /// The same over effects someone owns (a scene's, a diagnosis candidate's); they must outlive the process.
  EffectsProcess(const grinding::GrindingProcess& inner, const std::vector<std::unique_ptr<Effect>>& effects,
                 const machine::KinematicChain* chain = nullptr, double datum_face_z_mm = 0.0)
      : inner_(inner), chain_(own_axes(chain)), datum_face_z_mm_(datum_face_z_mm) {
    for (const auto& e : effects) effects_.push_back(e.get());
  }

  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override;
  /// The first-order pose error in w: the inner process's, plus J_twistw_q · (command offsets) (on another chain
  /// J_twistw_theta of its axes), plus the table's mounting twists — the linear counterpart of actual_wMg (equal to it
  /// to second order in the effects).
  machine::Vector6d error_twist_w(const grinding::PathPoint& pp) const override;
  double wheel_radius_error_mm(double v, const grinding::PathPoint& pp) const override;

private:
  static const machine::KinematicChain* own_axes(const machine::KinematicChain* chain) {
    return chain != nullptr && !chain->is_setting_chain() ? chain : nullptr;
  }
  /// Σ command_offset at pp, in the machine's axes (the chain's pose order on another chain).
  machine::Vector5d offset(const grinding::PathPoint& pp) const;
  grinding::PathPoint commanded(const grinding::PathPoint& pp, const machine::Vector5d& offset) const;

  const grinding::GrindingProcess& inner_;
  std::vector<const Effect*> effects_;
  const machine::KinematicChain* chain_ = nullptr; ///< null: the setting's coordinates (the CFXZAY)
  double datum_face_z_mm_ = 0.0;
};

} // namespace geartopo::effects
