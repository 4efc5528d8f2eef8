// geartopo — forward kinematics of the CFXZAY chain w → C → F → X → Z → A → Y → g, ideal and exact.
//
// Ideal (Eq. 11):  wMg = Rz(γ)⁻¹ · Tx(x) · Tz(z) · Rx(α) · Ty(y)
// Exact (Eq. 22, every error HTM exact, docs/machine-model.md §3):
//   FMC = S_C · Rz(γ + E_COC) · E(δ_c, ε_c)          wMF = FMC⁻¹   (w rides on the actual C axis line)
//   FMX = Tx(x) · E(δ_x, ε_x)
//   XMZ = Tz(z) · E(δ_z + (−z·S_xz, 0, 0), ε_z)                    (Eq. 16, with z·S_xz for the print's x·s_xz)
//   ZMA = S_A · Rx(α + E_AOA) · E(δ_a, ε_a) · S_A⁻¹                 (rotation about the actual A axis line)
//   AMY = Ty(y) · E(δ_y + (−y·S_xy, 0, −y·S_zy), ε_y)              (Eq. 17)
// with E(δ, ε) = T(δ)·Rx(εx)·Ry(εy)·Rz(εz), S_C = T(E_XOC, E_YOC, 0)·Rx(E_AOC)·Ry(E_BOC),
// S_A = T(0, E_YOA, E_ZOA)·Ry(E_BOA)·Rz(E_COA).
// Pose errors (Eq. 23): wMg_actual = E_w · wMg_ideal = wMg_ideal · E_g, reported as exact twists
// (translation; rotation vector) of E_w (in w) and of E_g (in g).
// Units: mm, rad.
#pragma once

#include "geartopo/machine/machine_data.hpp"
#include "geartopo/machine/machine_model.hpp"

namespace geartopo::machine {

/// Ideal wheel pose in the workpiece frame, the closed form of Eq. 11.
Pose ideal_wMg(const AxisPose& q);

/// The ideal wheel motion, in the wheel frame g, of moving X, Y and A by dx, dy, da from a pose with Y at y:
/// gMg′ = ideal_wMg(q)⁻¹ · ideal_wMg(q + (dx, dy, 0, da, 0)). With wMg = Rz(−c)·T(x,0,0)·T(0,0,z)·Rx(a)·T(0,y,0) the
/// C and Z factors cancel and Rx(−a)·T(dx,0,0)·Rx(a) = T(dx,0,0), so gMg′ = T(dx, −y, 0)·Rx(da)·T(0, y + dy, 0): the
/// rotation Rx(da) and the translation (dx, dy − (y + dy)·2 sin²(da/2), (y + dy) sin da) — independent of x, z, a, c.
Pose ideal_xya_motion_gMg(double y, double dx, double dy, double da);

/// The ideal chain's cumulative frames at q (w → F → X → Z → A → g): where the first-order error model and the
/// axis Jacobian place their twists.
struct IdealFrames {
  Pose wMF, wMX, wMZ, wMA, wMg;
};
IdealFrames ideal_frames(const AxisPose& q);

/// Ideal cumulative poses wMF_ideal … wMg_ideal into data (ideal_frames); returns data.wMg_ideal.
const Pose& ideal_kinematics(const AxisPose& q, MachineData& data);

/// Exact chain for given component values e (mm, rad): fills data.q, data.e and the local and cumulative
/// actual poses; returns data.wMg. For identification and finite differences in the components.
const Pose& actual_kinematics(const ErrorVector& e, const AxisPose& q, MachineData& data);

/// Exact chain with the model's errors at q (Eq. 22 without approximation); returns data.wMg.
const Pose& actual_wMg(const MachineModel& model, MachineData& data, const AxisPose& q);

/// The exact chain of one model evaluated pose after pose, recomputing only what moved: a profile grinder holds X, Y
/// and A fixed along a stroke, so along a stroke only the C and Z joints (and their components) change. Gives
/// actual_wMg(model, ·, q) bit for bit (the same joint functions; tests/machine). The constants of the axis lines
/// S_C, S_A are computed once. One evaluator per thread (it is mutable); `model` must be the one it was made with or a
/// copy of it (same id()).
class ChainEvaluator {
public:
  ChainEvaluator(const MachineModel& model, const AxisPose& q);
  std::uint64_t model_id() const { return model_id_; }
  /// Actual wheel pose at q.  wMg
  Pose actual_wMg(const MachineModel& model, const AxisPose& q);

private:
  std::uint64_t model_id_;
  ErrorVector e_;        ///< components at the axis positions of q_, 43×1
  AxisPose q_;           ///< the last pose
  Pose S_C_, S_A_, S_A_inverse_; ///< the C and A axis lines (constants)
  Pose wMF_, FMX_, ZMA_, AMY_;   ///< the C, X, A and Y joints at q_
  Pose ZMY_;                     ///< ZMA_·AMY_: the end of the chain, fixed while A and Y stand still (a stroke)
};

/// Pose error as twists: w = twist of E_w (in w), g = twist of E_g (in g); (translation mm; rotation rad).
struct PoseErrorTwists {
  Vector6d w; ///< 6×1, workpiece frame: E_w = wMg_actual · wMg_ideal⁻¹ (Eq. 23)
  Vector6d g; ///< 6×1, wheel frame: E_g = wMg_ideal⁻¹ · wMg_actual
};

/// Exact pose error at q with the model's errors (replaces the small-angle Eq. 24).
PoseErrorTwists exact_pose_error(const MachineModel& model, MachineData& data, const AxisPose& q);
/// Same for given component values.
PoseErrorTwists exact_pose_error(const ErrorVector& e, const AxisPose& q, MachineData& data);

} // namespace geartopo::machine
