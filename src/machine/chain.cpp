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

const Pose& actual_kinematics(const ErrorVector& e, const AxisPose& q, MachineData& data) {
  data.q = q;
  data.e = e;
  const auto E = [&](ComponentId k) { return e(index(k)); };

  // C: the table (and with it the workpiece frame w) turns about the actual C axis line S_C.
  const Pose S_C = translation(E(E_XOC), E(E_YOC), 0.0) * Rx(E(E_AOC)) * Ry(E(E_BOC));
  const Pose FMC = S_C * Rz(q.c + E(E_COC)) *
                   error_htm(v3(e, delta_xc, delta_yc, delta_zc), v3(e, epsilon_xc, epsilon_yc, epsilon_zc));
  data.wMF = FMC.inverse(Eigen::Isometry);

  // X (Eq. 15).
  data.FMX = slide({q.x + E(delta_xx), E(delta_yx), E(delta_zx)}, v3(e, epsilon_xx, epsilon_yx, epsilon_zx));
  // Z (Eq. 16; squareness scales with the Z travel z).
  data.XMZ = slide({E(delta_xz) - q.z * E(S_xz), E(delta_yz), q.z + E(delta_zz)},
                   v3(e, epsilon_xz, epsilon_yz, epsilon_zz));
  // A (Eq. 21 style, about the actual axis line S_A; at α = 0 and no error motion ZMA = I).
  const Pose S_A = translation(0.0, E(E_YOA), E(E_ZOA)) * Ry(E(E_BOA)) * Rz(E(E_COA));
  data.ZMA = S_A * Rx(q.a + E(E_AOA)) *
             error_htm(v3(e, delta_xa, delta_ya, delta_za), v3(e, epsilon_xa, epsilon_ya, epsilon_za)) *
             S_A.inverse(Eigen::Isometry);
  // Y (Eq. 17).
  data.AMY = slide({E(delta_xy) - q.y * E(S_xy), q.y + E(delta_yy), E(delta_zy) - q.y * E(S_zy)},
                   v3(e, epsilon_xy, epsilon_yy, epsilon_zy));

  data.wMX = data.wMF * data.FMX;
  data.wMZ = data.wMX * data.XMZ;
  data.wMA = data.wMZ * data.ZMA;
  data.wMg = data.wMA * data.AMY;
  return data.wMg;
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
