// geartopo — the wheel pose of any kinematic chain (kinematic_chain.hpp) with its 43 error components: exact, to
// first order, and its Jacobians in the chain's own axes (docs/machine-model.md, "The chain as data").
//
// Exact: wMg = Π_i J_i(θ_i, e), a workpiece-side joint inverted (src/machine/chain_joints.hpp writes each joint).
// First order: every component enters one joint i as a near-identity factor; with ξ_k(θ) the spatial twist (in the
// joint's parent frame) of d J_i/d e_k · J_i⁻¹ at e = 0,
//   J_twistw_e(:, k) = Ad(wM_i) · ξ_k            (tool side: wM_i the frame before joint i)
//   J_twistw_e(:, k) = −Ad(wM_{i+1}) · ξ_k       (workpiece side: the factor is J_i⁻¹, d(J⁻¹)·J = −Ad(J⁻¹)·ξ)
// and J_twistg_e = Ad(wMg⁻¹) · J_twistw_e; the axis Jacobians the same with ξ the joint's own motion twist.
// On the CFXZAY these equal chain.hpp / first_order.hpp / jacobian.hpp, the compiled-in chain (tests/machine).
// Units: twists (mm; rad); θ and e in mm and rad.
#pragma once

#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/kinematic_chain.hpp"
#include "geartopo/machine/machine_data.hpp"

namespace geartopo::machine {

/// The chain's actual wheel pose at θ with component values e (mm, rad), every error HTM exact.  wMg
Pose actual_wMg(const KinematicChain& chain, const ErrorVector& e, const AxisValues& theta);

/// Exact pose-error twists at θ: E_w = wMg·wMg_ideal⁻¹ (in w), E_g = wMg_ideal⁻¹·wMg (in g).
PoseErrorTwists exact_pose_error(const KinematicChain& chain, const ErrorVector& e, const AxisValues& theta);

/// First-order pose-error twist per component at θ, in w and in g.  6×43 each
void error_jacobians(const KinematicChain& chain, const AxisValues& theta, Matrix6E& J_twistw_e, Matrix6E& J_twistg_e);

/// The ideal wheel pose's spatial twist (in w) per unit of each of the chain's axes (pose order), at θ.  6×5
Matrix65 J_twistw_theta(const KinematicChain& chain, const AxisValues& theta);
/// The same as a body twist (in g).  6×5
Matrix65 J_twistg_theta(const KinematicChain& chain, const AxisValues& theta);

/// The model's component values at the chain's axis positions θ (each component at its own axis' position: the
/// model's tables are functions of the chain's axes, slot by slot).  43×1
inline void errors_at(const MachineModel& model, const AxisValues& theta, ErrorVector& e) {
  model.errors_at(AxisPose::from_vector(theta.v), e);
}

} // namespace geartopo::machine
