// geartopo — per-evaluation workspace of the machine model (Pinocchio's Data): every transform, error value
// and Jacobian of the last evaluation, in fixed-size storage so that repeated evaluations allocate nothing.
//
// Frames (docs/machine-model.md): w workpiece (= C table), F frame (bed), X, Z, A slides, Y slide = g wheel.
// A pose aMb is frame b expressed in frame a. Units: mm, rad.
#pragma once

#include "geartopo/machine/axis_pose.hpp"
#include "geartopo/machine/error_component.hpp"
#include "geartopo/machine/twist.hpp"

#include <Eigen/Core>

namespace geartopo::machine {

using Matrix65 = Eigen::Matrix<double, 6, kAxisCount>;          ///< twist per axis command, 6×5
using Matrix6E = Eigen::Matrix<double, 6, kComponentCount>;     ///< twist per error component, 6×43

struct MachineData {
  AxisPose q;      ///< pose of the last evaluation
  ErrorVector e;   ///< component values at q (mm, rad), 43×1
  ErrorVector de;  ///< their rates along their own axis (per mm or per rad), 43×1

  // Exact chain (actual_kinematics), local joint transforms parent→child, error HTMs included.
  Pose wMF = Pose::Identity(); ///< C joint: frame F in the workpiece frame (inverse of FMC)
  Pose FMX = Pose::Identity(); ///< X slide in F
  Pose XMZ = Pose::Identity(); ///< Z slide in X
  Pose ZMA = Pose::Identity(); ///< A body in Z
  Pose AMY = Pose::Identity(); ///< Y slide in A; the wheel frame g is the Y frame (YMg = I)
  // Exact chain, cumulative.
  Pose wMX = Pose::Identity(), wMZ = Pose::Identity(), wMA = Pose::Identity();
  Pose wMg = Pose::Identity(); ///< actual wheel pose (Eq. 22 without approximation)

  // Ideal chain (ideal_kinematics), cumulative: the frames at which the first-order model applies errors.
  Pose wMF_ideal = Pose::Identity(), wMX_ideal = Pose::Identity(), wMZ_ideal = Pose::Identity();
  Pose wMA_ideal = Pose::Identity();
  Pose wMg_ideal = Pose::Identity(); ///< Eq. 11

  // First-order error sensitivities (first_order.hpp): column k = d twist / d e(k) at q.
  Matrix6E J_twistw_e = Matrix6E::Zero(); ///< pose-error twist in w per component, 6×43
  Matrix6E J_twistg_e = Matrix6E::Zero(); ///< pose-error twist in g per component, 6×43

  // Jacobians of the actual wheel pose w.r.t. the axis commands (jacobian.hpp).
  Matrix65 J_twistw_q = Matrix65::Zero(); ///< spatial twist (in w) per axis, 6×5
  Matrix65 J_twistg_q = Matrix65::Zero(); ///< body twist (in g) per axis, 6×5
};

} // namespace geartopo::machine
