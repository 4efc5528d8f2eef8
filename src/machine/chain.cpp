// geartopo — ideal and exact forward kinematics of the CFXZAY grinder (see chain.hpp). Units: mm, rad.
#include "geartopo/machine/chain.hpp"

#include "geartopo/machine/transforms.hpp"

#include <cmath>

namespace geartopo::machine {

namespace {

using enum ComponentId;

Eigen::Vector3d v3(const ErrorVector& e, ComponentId a, ComponentId b, ComponentId c) {
  return {e(index(a)), e(index(b)), e(index(c))};
}

/// [R(ε) | p]: a linear slide's exact HTM, nominal travel and errors already summed in p (Eqs. 15–17).
Pose slide(const Eigen::Vector3d& p, const Eigen::Vector3d& eps) { return error_htm(p, eps); }

double E(const ErrorVector& e, ComponentId k) { return e(index(k)); }

} // namespace

Pose ideal_wMg(const AxisPose& q) {
  // Eq. 11, element by element.
  const double cg = std::cos(q.c), sg = std::sin(q.c), ca = std::cos(q.a), sa = std::sin(q.a);
  Eigen::Matrix4d m;
  m << cg, ca * sg, -sa * sg, q.y * ca * sg + q.x * cg, //
      -sg, ca * cg, -sa * cg, q.y * ca * cg - q.x * sg, //
      0.0, sa, ca, q.z + q.y * sa,                      //
      0.0, 0.0, 0.0, 1.0;
  return Pose(m);
}

Pose ideal_xya_motion_gMg(double y, double dx, double dy, double da) {
  const double s = std::sin(da), h = std::sin(0.5 * da), c = std::cos(da);
  Pose m = Pose::Identity();
  m.linear() << 1.0, 0.0, 0.0, //
      0.0, c, -s,               //
      0.0, s, c;
  m.translation() = Eigen::Vector3d(dx, dy - (y + dy) * 2.0 * h * h, (y + dy) * s);
  return m;
}

IdealFrames ideal_frames(const AxisPose& q) {
  IdealFrames f;
  f.wMF = Rz(-q.c);
  f.wMX = f.wMF * translation(q.x, 0.0, 0.0);
  f.wMZ = f.wMX * translation(0.0, 0.0, q.z);
  f.wMA = f.wMZ * Rx(q.a);
  f.wMg = f.wMA * translation(0.0, q.y, 0.0);
  return f;
}

const Pose& ideal_kinematics(const AxisPose& q, MachineData& data) {
  const IdealFrames f = ideal_frames(q);
  data.wMF_ideal = f.wMF;
  data.wMX_ideal = f.wMX;
  data.wMZ_ideal = f.wMZ;
  data.wMA_ideal = f.wMA;
  data.wMg_ideal = f.wMg;
  return data.wMg_ideal;
}

namespace {

// The joints of the exact chain, each a function of its own axis' command and components and of constants only (the
// squareness and location components): ChainEvaluator recomputes a joint only when its axis moved, and
// actual_kinematics and ChainEvaluator give the same bits because they share these functions.
Pose c_axis_line(const ErrorVector& e) { return translation(E(e, E_XOC), E(e, E_YOC), 0.0) * Rx(E(e, E_AOC)) * Ry(E(e, E_BOC)); }
Pose a_axis_line(const ErrorVector& e) { return translation(0.0, E(e, E_YOA), E(e, E_ZOA)) * Ry(E(e, E_BOA)) * Rz(E(e, E_COA)); }

/// C: the table (and with it the workpiece frame w) turns about the actual C axis line S_C; returns wMF = FMC⁻¹.
Pose c_joint_wMF(const ErrorVector& e, double c, const Pose& S_C) {
  const Pose FMC = S_C * Rz(c + E(e, E_COC)) *
                   error_htm(v3(e, delta_xc, delta_yc, delta_zc), v3(e, epsilon_xc, epsilon_yc, epsilon_zc));
  return FMC.inverse(Eigen::Isometry);
}
/// X (Eq. 15).
Pose x_joint(const ErrorVector& e, double x) {
  return slide({x + E(e, delta_xx), E(e, delta_yx), E(e, delta_zx)}, v3(e, epsilon_xx, epsilon_yx, epsilon_zx));
}
/// Z (Eq. 16; squareness scales with the Z travel z).
Pose z_joint(const ErrorVector& e, double z) {
  return slide({E(e, delta_xz) - z * E(e, S_xz), E(e, delta_yz), z + E(e, delta_zz)}, v3(e, epsilon_xz, epsilon_yz, epsilon_zz));
}
/// A (Eq. 21 style, about the actual axis line S_A; at α = 0 and no error motion ZMA = I).
Pose a_joint(const ErrorVector& e, double a, const Pose& S_A, const Pose& S_A_inverse) {
  return S_A * Rx(a + E(e, E_AOA)) *
         error_htm(v3(e, delta_xa, delta_ya, delta_za), v3(e, epsilon_xa, epsilon_ya, epsilon_za)) * S_A_inverse;
}
/// Y (Eq. 17).
Pose y_joint(const ErrorVector& e, double y) {
  return slide({E(e, delta_xy) - y * E(e, S_xy), y + E(e, delta_yy), E(e, delta_zy) - y * E(e, S_zy)},
               v3(e, epsilon_xy, epsilon_yy, epsilon_zy));
}

} // namespace

const Pose& actual_kinematics(const ErrorVector& e, const AxisPose& q, MachineData& data) {
  data.q = q;
  data.e = e;
  const Pose S_A = a_axis_line(e);
  data.wMF = c_joint_wMF(e, q.c, c_axis_line(e));
  data.FMX = x_joint(e, q.x);
  data.XMZ = z_joint(e, q.z);
  data.ZMA = a_joint(e, q.a, S_A, S_A.inverse(Eigen::Isometry));
  data.AMY = y_joint(e, q.y);

  data.wMX = data.wMF * data.FMX;
  data.wMZ = data.wMX * data.XMZ;
  data.wMA = data.wMZ * data.ZMA;
  data.wMg = data.wMZ * (data.ZMA * data.AMY); // associated as ChainEvaluator, which keeps ZMA·AMY while A, Y stand
  return data.wMg;
}

ChainEvaluator::ChainEvaluator(const MachineModel& model, const AxisPose& q) : model_id_(model.id()) {
  model.errors_at(q, e_);
  q_ = q;
  S_C_ = c_axis_line(e_);
  S_A_ = a_axis_line(e_);
  S_A_inverse_ = S_A_.inverse(Eigen::Isometry);
  wMF_ = c_joint_wMF(e_, q.c, S_C_);
  FMX_ = x_joint(e_, q.x);
  ZMA_ = a_joint(e_, q.a, S_A_, S_A_inverse_);
  AMY_ = y_joint(e_, q.y);
  ZMY_ = ZMA_ * AMY_;
}

Pose ChainEvaluator::actual_wMg(const MachineModel& model, const AxisPose& q) {
  // Bit for bit actual_kinematics: every joint is recomputed from the same inputs whenever its axis moved, and the
  // position-dependent components of an axis enter only that axis' joint (the others are constants).
  if (q.c != q_.c) {
    model.axis_errors_at(Axis::C, q.c, e_);
    wMF_ = c_joint_wMF(e_, q.c, S_C_);
  }
  if (q.x != q_.x) {
    model.axis_errors_at(Axis::X, q.x, e_);
    FMX_ = x_joint(e_, q.x);
  }
  const bool a_or_y_moved = q.a != q_.a || q.y != q_.y;
  if (q.a != q_.a) {
    model.axis_errors_at(Axis::A, q.a, e_);
    ZMA_ = a_joint(e_, q.a, S_A_, S_A_inverse_);
  }
  if (q.y != q_.y) {
    model.axis_errors_at(Axis::Y, q.y, e_);
    AMY_ = y_joint(e_, q.y);
  }
  if (a_or_y_moved) ZMY_ = ZMA_ * AMY_;
  model.axis_errors_at(Axis::Z, q.z, e_);
  q_ = q;
  return wMF_ * FMX_ * z_joint(e_, q.z) * ZMY_;
}

const Pose& actual_wMg(const MachineModel& model, MachineData& data, const AxisPose& q) {
  model.errors_at(q, data.e);
  return actual_kinematics(data.e, q, data);
}

PoseErrorTwists exact_pose_error(const ErrorVector& e, const AxisPose& q, MachineData& data) {
  actual_kinematics(e, q, data);
  ideal_kinematics(q, data);
  const Pose gMw_ideal = data.wMg_ideal.inverse(Eigen::Isometry);
  return {pose_error_twist(data.wMg * gMw_ideal), pose_error_twist(gMw_ideal * data.wMg)};
}

PoseErrorTwists exact_pose_error(const MachineModel& model, MachineData& data, const AxisPose& q) {
  model.errors_at(q, data.e);
  return exact_pose_error(data.e, q, data); // aliasing data.e is fine: actual_kinematics copies e to itself
}

} // namespace geartopo::machine
