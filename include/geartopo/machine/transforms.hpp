// geartopo — elementary homogeneous transforms (paper Eqs. 1–9) and the exact error HTM.
// Units: mm, rad.
#pragma once

#include "geartopo/machine/twist.hpp"

#include <cmath>

namespace geartopo::machine {

/// Translation by (x, y, z) mm (Eqs. 2–4).
inline Pose translation(double x, double y, double z) {
  Pose m = Pose::Identity();
  m.translation() << x, y, z;
  return m;
}
inline Pose translation(const Eigen::Vector3d& p) { return translation(p.x(), p.y(), p.z()); }

/// Rotations about the frame's own x, y, z axes (Eqs. 6–8), right-handed, angle in rad.  // 3×3
inline Eigen::Matrix3d rot_x(double t) {
  const double c = std::cos(t), s = std::sin(t);
  Eigen::Matrix3d r;
  r << 1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c;
  return r;
}
inline Eigen::Matrix3d rot_y(double t) {
  const double c = std::cos(t), s = std::sin(t);
  Eigen::Matrix3d r;
  r << c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c;
  return r;
}
inline Eigen::Matrix3d rot_z(double t) {
  const double c = std::cos(t), s = std::sin(t);
  Eigen::Matrix3d r;
  r << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return r;
}
inline Pose Rx(double t) { Pose m = Pose::Identity(); m.linear() = rot_x(t); return m; }
inline Pose Ry(double t) { Pose m = Pose::Identity(); m.linear() = rot_y(t); return m; }
inline Pose Rz(double t) { Pose m = Pose::Identity(); m.linear() = rot_z(t); return m; }

/// Exact angular-error rotation R(ε) = Rx(εx)·Ry(εy)·Rz(εz) — the order of Eq. 9, whose first-order form
/// is Eq. 10 / Eq. 13. We keep the exact matrix: no small-angle approximation anywhere in the "exact" chain.
inline Eigen::Matrix3d error_rotation(const Eigen::Vector3d& eps) {
  return rot_x(eps.x()) * rot_y(eps.y()) * rot_z(eps.z());
}

/// Exact error HTM E(δ, ε) = T(δ)·R(ε) (Eq. 9 with δ the translation and ε the angles, Eqs. 12–15, 19).
inline Pose error_htm(const Eigen::Vector3d& delta, const Eigen::Vector3d& eps) {
  Pose m = Pose::Identity();
  m.linear() = error_rotation(eps);
  m.translation() = delta;
  return m;
}

/// Body angular velocity of R(ε(q)) = Rx·Ry·Rz: vee(Rᵀ·dR/dq) given ε and dε/dq (rad per unit of q).
inline Eigen::Vector3d error_rotation_body_rate(const Eigen::Vector3d& eps, const Eigen::Vector3d& deps) {
  const Eigen::Matrix3d rz_t = rot_z(eps.z()).transpose();
  const Eigen::Matrix3d ry_t = rot_y(eps.y()).transpose();
  return rz_t * (ry_t * Eigen::Vector3d::UnitX() * deps.x() + Eigen::Vector3d::UnitY() * deps.y()) +
         Eigen::Vector3d::UnitZ() * deps.z();
}

} // namespace geartopo::machine
