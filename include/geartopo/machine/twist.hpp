// geartopo — twists and adjoints: the small-motion algebra of the machine model.
//
// A twist is a 6-vector (v; ω): v translation (mm), ω rotation (rad), both expressed in one named frame.
// For a pose aMb and a twist ξ_b expressed in frame b, ξ_a = Ad(aMb)·ξ_b, with
//   Ad(aMb) = [ R  [p]×R ; 0  R ]   (6×6)
// This is the paper's differential motion matrix (Eq. 25) up to direction: D[aMb] = Ad(aMb⁻¹) maps a twist
// from frame a into frame b ("Paul's differential transform").
// Units: mm, rad.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace geartopo::machine {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
/// Rigid transform aMb: pose of frame b in frame a (maps b coordinates to a coordinates).
using Pose = Eigen::Isometry3d;

/// Skew matrix: skew(p)·v = p × v.  // 3×3
inline Eigen::Matrix3d skew(const Eigen::Vector3d& p) {
  Eigen::Matrix3d s;
  s << 0.0, -p.z(), p.y(), p.z(), 0.0, -p.x(), -p.y(), p.x(), 0.0;
  return s;
}

/// Adjoint of aMb: transports a twist from frame b to frame a (Eq. 25 inverted, see header).  // 6×6
inline Matrix6d adjoint(const Pose& aMb) {
  const Eigen::Matrix3d R = aMb.linear();
  Matrix6d ad;
  ad.topLeftCorner<3, 3>() = R;
  ad.topRightCorner<3, 3>() = skew(aMb.translation()) * R;
  ad.bottomLeftCorner<3, 3>().setZero();
  ad.bottomRightCorner<3, 3>() = R;
  return ad;
}

/// Rotation vector (axis·angle, rad) of a rotation matrix, angle in [0, π]. Exact, no small-angle
/// approximation; accurate down to angles of 1e-300 because it goes through the quaternion
/// (angle = 2·atan2(|q_v|, q_w)), not through acos of the trace.
inline Eigen::Vector3d rotation_vector(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond q(R);
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double n = q.vec().norm();
  if (n == 0.0) return Eigen::Vector3d::Zero();
  return (2.0 * std::atan2(n, q.w()) / n) * q.vec();
}

/// The pose-error twist of a near-identity transform E: (translation of E; rotation vector of E).
/// This is the "(t, θ)" parametrisation of R³×SO(3); it equals the SE(3) matrix logarithm to first
/// order, and unlike the logarithm its translation part is exactly E's translation (the paper's
/// p_x, p_y, p_z of Eq. 24).  // 6×1
inline Vector6d pose_error_twist(const Pose& E) {
  Vector6d xi;
  xi.head<3>() = E.translation();
  xi.tail<3>() = rotation_vector(E.linear());
  return xi;
}

} // namespace geartopo::machine
