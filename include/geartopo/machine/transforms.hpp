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

/// Below this the Taylor series of sin_cos replace the library's sin and cos (rad).
inline constexpr double kSmallAngleRad = 1e-3;

/// sin t and cos t. For |t| < 10⁻³ rad (the error angles: µrad) by their Taylor series, sin to t⁵ and cos to t⁴: the
/// first terms left out, t⁷/5040 and t⁶/720, are below 2·10⁻²² and 1.4·10⁻²¹ relative, far under double rounding (1.1·10⁻¹⁶), so
/// this is exact to rounding and not a small-angle approximation; larger angles go to the library.
inline void sin_cos(double t, double& s, double& c) {
  if (std::abs(t) < kSmallAngleRad) {
    const double t2 = t * t;
    s = t * (1.0 - t2 / 6.0 * (1.0 - t2 / 20.0));
    c = 1.0 - t2 / 2.0 * (1.0 - t2 / 12.0);
    return;
  }
  s = std::sin(t);
  c = std::cos(t);
}

/// Exact angular-error rotation R(ε) = Rx(εx)·Ry(εy)·Rz(εz) — the order of Eq. 9, whose first-order form
/// is Eq. 10 / Eq. 13. We keep the exact matrix: no small-angle approximation anywhere in the "exact" chain. The
/// product written out (the two 3×3 products cost as much as the sines) and sin_cos for the µrad angles.
inline Eigen::Matrix3d error_rotation(const Eigen::Vector3d& eps) {
  double sa, ca, sb, cb, sc, cc;
  sin_cos(eps.x(), sa, ca);
  sin_cos(eps.y(), sb, cb);
  sin_cos(eps.z(), sc, cc);
  Eigen::Matrix3d r;
  r << cb * cc, -cb * sc, sb,                                //
      sa * sb * cc + ca * sc, ca * cc - sa * sb * sc, -sa * cb, //
      sa * sc - ca * sb * cc, sa * cc + ca * sb * sc, ca * cb;
  return r;
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
