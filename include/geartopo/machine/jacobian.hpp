// geartopo — Jacobians of the wheel pose with respect to the axis commands q = (X, Y, Z, A, C)
// (the paper's J_M, Eqs. 25–28, derived again: the printed Eq. 27/28 have wrong signs and misplaced terms,
// docs/machine-model.md §5).
//
// J_twistg_q: body twist of the wheel (in g) per unit command:  wMg(q + dq) ≈ wMg(q) · exp(J_twistg_q · dq)
// J_twistw_q: spatial twist (in w) per unit command:           wMg(q + dq) ≈ exp(J_twistw_q · dq) · wMg(q)
// J_twistw_q = Ad(wMg) · J_twistg_q. Columns X, Y, Z in (mm; rad) per mm, A and C per rad.
#pragma once

#include "geartopo/machine/chain.hpp"

namespace geartopo::machine {

/// Ideal chain (Eq. 11), wheel frame: corrects Eq. 28's J_M.  // 6×5
Matrix65 J_twistg_q(const AxisPose& q);
/// Ideal chain, workpiece frame.  // 6×5
Matrix65 J_twistw_q(const AxisPose& q);

/// Actual chain with the model's errors, including the errors' variation with the axis positions
/// (spline / polynomial slopes): fills data.J_twistg_q and data.J_twistw_q (6×5) and the actual poses.
void actual_jacobians(const MachineModel& model, MachineData& data, const AxisPose& q);

} // namespace geartopo::machine
