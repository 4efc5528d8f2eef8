// geartopo — first-order (linearised) error model of the CFXZAY chain, derived, not transcribed
// (docs/machine-model.md §4; replaces the paper's Eq. 24 expressions for p_x … η_z).
//
// Every error enters the exact chain as a near-identity factor exp(ξ_k) placed at some frame j of the ideal
// chain; to first order the pose error twist in w is the sum of those factors transported to w:
//   twist_w = Σ_k Ad(wM_j(k)) · ξ_k = J_twistw_e(q) · e,      twist_g = Ad(wMg⁻¹) · twist_w = J_twistg_e(q) · e
// where ξ_k is the unit twist of component k at its frame (scaled by −y, −z for squareness, negated where the
// chain traverses a joint backwards: the C joint, S_A⁻¹). J_twist*_e depend on q only.
// Units: twist (mm; rad), e (mm, rad).
#pragma once

#include "geartopo/machine/chain.hpp"

namespace geartopo::machine {

/// d twist / d e at q, both frames: fills data.J_twistw_e and data.J_twistg_e (6×43) and the ideal poses.
/// Column k is the pose error that a unit value of component k causes at q.
void error_jacobians(const AxisPose& q, MachineData& data);

/// First-order pose error twists J_twist*_e(q) · e for given component values. No allocation.
PoseErrorTwists twist_linear(const ErrorVector& e, const AxisPose& q, MachineData& data);
/// Same with the model's errors at q (data.e is set).
PoseErrorTwists twist_linear(const MachineModel& model, MachineData& data, const AxisPose& q);

/// The workpiece-frame twist J_twistw_e(q) · e alone, by transporting the error twists grouped per frame of the
/// ideal chain (six transports instead of a 6×43 Jacobian and two 6×43 products). Equal to twist_linear(e, q, …).w
/// to rounding (tests/machine/test_exact_vs_first_order.cpp); the simulator's linear method calls it once per
/// point. No workspace, no allocation.
Vector6d twist_w_linear(const ErrorVector& e, const AxisPose& q);

} // namespace geartopo::machine
