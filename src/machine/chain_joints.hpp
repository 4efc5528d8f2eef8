// geartopo machine, private — one joint of a kinematic chain, ideal and with its errors, parent → child as the machine
// is built (docs/machine-model.md §3). Shared by the exact chain (chain.cpp), its evaluator, the first-order model
// (first_order.cpp) and the Jacobians (jacobian.cpp), so that all of them place every error at the same frame.
//
//   linear:  M = T(o) · T(θ·d + δ − Σ θ·S_jk·u_j) · R(ε)                      (Eqs. 15–17: δ, ε in the parent frame)
//   rotary:  M = T(o) · S · R_d(θ + E_0) · E(δ, ε) · S⁻¹                      (Eq. 21: δ, ε in the turning body)
//            the workpiece spindle without the trailing S⁻¹: the gear sits on the actual axis line
//   S = T(offsets across the axis) · R_p1(tilt) · R_p2(tilt), the ISO 230-7 location of the axis line
// with d = ±e_dir, R_d(t) the right-handed turn about d, E(δ, ε) = T(δ)·Rx(εx)·Ry(εy)·Rz(εz). A workpiece-side joint
// enters wMg inverted. Units: mm, rad.
#pragma once

#include "geartopo/machine/kinematic_chain.hpp"
#include "geartopo/machine/transforms.hpp"

namespace geartopo::machine::detail {

inline Eigen::Vector3d v3(const ErrorVector& e, int first) { return {e(first), e(first + 1), e(first + 2)}; }

/// Ad(aMb)·ξ without forming the 6×6 adjoint: (R v + p × R ω; R ω).  // 6×1
inline Vector6d transport(const Pose& aMb, const Vector6d& xi) {
  const Eigen::Vector3d w = aMb.linear() * xi.tail<3>();
  Vector6d out;
  out.head<3>() = aMb.linear() * xi.head<3>() + aMb.translation().cross(w);
  out.tail<3>() = w;
  return out;
}

/// Rotation about coordinate axis `dir` by t (rad).
inline Eigen::Matrix3d coordinate_rotation(int dir, double t) {
  return dir == 0 ? rot_x(t) : dir == 1 ? rot_y(t) : rot_z(t);
}
inline Pose coordinate_turn(int dir, double t) {
  Pose m;
  m.linear() = coordinate_rotation(dir, t);
  m.translation().setZero();
  m.makeAffine();
  return m;
}

/// S: the actual axis line of a rotary joint (its five location errors at j.location …).
inline Pose axis_line(const Joint& j, const ErrorVector& e) {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  offset(j.perpendicular[0]) = e(j.location);
  offset(j.perpendicular[1]) = e(j.location + 1);
  return translation(offset) * coordinate_turn(j.perpendicular[0], e(j.location + 2)) *
         coordinate_turn(j.perpendicular[1], e(j.location + 3));
}

/// The twist of S to first order: (offsets; tilts) at the pivot.  // 6×1
inline Vector6d axis_line_twist(const Joint& j, const ErrorVector& e) {
  Vector6d s = Vector6d::Zero();
  s(j.perpendicular[0]) = e(j.location);
  s(j.perpendicular[1]) = e(j.location + 1);
  s(3 + j.perpendicular[0]) = e(j.location + 2);
  s(3 + j.perpendicular[1]) = e(j.location + 3);
  return s;
}

/// The translation of a linear joint: travel, straightness and positioning error, squareness (and the offset).
inline Eigen::Vector3d linear_translation(const Joint& j, const ErrorVector& e, double theta) {
  Eigen::Vector3d t = v3(e, j.motion);
  t(j.dir) = t(j.dir) + j.sign * theta;
  for (int k = 0; k < j.squareness_count; ++k)
    t += (-(theta * e(j.squareness[static_cast<std::size_t>(k)]))) * j.lean[static_cast<std::size_t>(k)];
  if (j.has_offset) t += j.offset;
  return t;
}

/// The joint parent → child with its errors. `S`, `S_inverse`: the rotary joint's axis line and its inverse (constants,
/// cached by the evaluators); ignored for a linear joint.
inline Pose exact_joint(const Joint& j, const ErrorVector& e, double theta, const Pose& S, const Pose& S_inverse) {
  if (j.kind == AxisKind::Linear) return error_htm(linear_translation(j, e, theta), v3(e, j.motion + 3));
  Pose M = S * coordinate_turn(j.dir, j.sign * (theta + e(j.location + 4))) *
           error_htm(v3(e, j.motion), v3(e, j.motion + 3));
  if (!j.carries_workpiece) M = M * S_inverse;
  if (j.has_offset) M = translation(j.offset) * M;
  return M;
}

/// The joint as it enters wMg: inverted on the workpiece side.
inline Pose chain_joint(const Joint& j, const ErrorVector& e, double theta, const Pose& S, const Pose& S_inverse) {
  const Pose M = exact_joint(j, e, theta, S, S_inverse);
  return j.workpiece_side ? M.inverse(Eigen::Isometry) : M;
}

/// The ideal joint parent → child.
inline Pose ideal_joint(const Joint& j, double theta) {
  Pose M = Pose::Identity();
  if (j.kind == AxisKind::Linear) M.translation()(j.dir) = j.sign * theta;
  else M.linear() = coordinate_rotation(j.dir, j.sign * theta);
  if (j.has_offset) M.translation() += j.offset;
  return M;
}

/// The ideal chain's frames from the workpiece: frame[0] = w, frame[i + 1] = frame[i]·(joint i as it enters wMg), so
/// frame[5] = wMg; pivot[i] the frame at rotary joint i's axis line before its turn (the parent after T(o) on the tool
/// side, the child turned back on the workpiece side).
struct ChainFrames {
  std::array<Pose, kAxisCount + 1> frame;
  std::array<Pose, kAxisCount> pivot;
};

inline ChainFrames chain_frames(const KinematicChain& chain, const AxisValues& theta) {
  ChainFrames f;
  f.frame[0] = Pose::Identity();
  for (int i = 0; i < kAxisCount; ++i) {
    const Joint& j = chain.joints()[static_cast<std::size_t>(i)];
    const Pose M = ideal_joint(j, theta[j.slot]);
    const Pose& before = f.frame[static_cast<std::size_t>(i)];
    Pose& after = f.frame[static_cast<std::size_t>(i + 1)];
    after = before * (j.workpiece_side ? M.inverse(Eigen::Isometry) : M);
    if (j.kind == AxisKind::Rotary)
      f.pivot[static_cast<std::size_t>(i)] =
          j.workpiece_side ? Pose(before * coordinate_turn(j.dir, -j.sign * theta[j.slot]))
                           : (j.has_offset ? Pose(before * translation(j.offset)) : before);
  }
  return f;
}

} // namespace geartopo::machine::detail
