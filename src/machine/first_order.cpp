// geartopo — first-order error sensitivities by adjoint transport (first_order.hpp). Units: mm, rad.
#include "geartopo/machine/first_order.hpp"

namespace geartopo::machine {

namespace {
using enum ComponentId;

// Ad(aMb)·ξ without forming the 6×6 adjoint: (R v + p × R ω; R ω).
Vector6d transport(const Pose& aMb, const Vector6d& xi) {
  const Eigen::Vector3d w = aMb.linear() * xi.tail<3>();
  Vector6d out;
  out.head<3>() = aMb.linear() * xi.head<3>() + aMb.translation().cross(w);
  out.tail<3>() = w;
  return out;
}

// The six motion components of an axis as a twist (δx, δy, δz; εx, εy, εz) at that axis's frame.
Vector6d motion_twist(const ErrorVector& e, Axis axis) {
  Vector6d xi;
  for (int k = 0; k < 6; ++k) xi(k) = e(index(motion_component(axis, k)));
  return xi;
}
} // namespace

void error_jacobians(const AxisPose& q, MachineData& data) {
  data.q = q;
  ideal_kinematics(q, data);
  Matrix6E& J = data.J_twistw_e;
  J.setZero();
  const auto col = [&](ComponentId k) { return J.col(index(k)); };

  // Frames at which the error factors sit in the ideal chain w → F → X → Z → A → g.
  const Matrix6d AdF = adjoint(data.wMF_ideal); // = Ad(Rz(−γ))
  const Matrix6d AdX = adjoint(data.wMX_ideal);
  const Matrix6d AdZ = adjoint(data.wMZ_ideal);
  const Matrix6d AdA = adjoint(data.wMA_ideal);
  const Matrix6d Adg = adjoint(data.wMg_ideal);

  for (int k = 0; k < 6; ++k) {
    // C: wMF = E_C⁻¹ · Rz(−E_COC) · Rz(−γ) · S_C⁻¹. E_C⁻¹ sits at w itself: −ξ.
    J.col(index(motion_component(Axis::C, k))) = -Matrix6d::Identity().col(k);
    // X, Z, Y: T(travel) · E(δ, ε): the error twist (δ; ε) sits at the slide's own frame.
    J.col(index(motion_component(Axis::X, k))) = AdX.col(k);
    J.col(index(motion_component(Axis::Z, k))) = AdZ.col(k);
    J.col(index(motion_component(Axis::Y, k))) = Adg.col(k);
    // A: S_A · Rx(α) · Rx(E_AOA) · E_A · S_A⁻¹: E_A sits at the A frame (after the rotation).
    J.col(index(motion_component(Axis::A, k))) = AdA.col(k);
  }

  // Squareness: translations −y·S_xy (x), −y·S_zy (z) in the Y slide's frame, −z·S_xz (x) in the Z slide's.
  col(S_xy) = -q.y * Adg.col(0);
  col(S_zy) = -q.y * Adg.col(2);
  col(S_xz) = -q.z * AdZ.col(0);

  // C axis line: S_C⁻¹ sits at F (right of Rz(−γ)), twist of S_C = (E_XOC, E_YOC, 0; E_AOC, E_BOC, 0).
  col(E_XOC) = -AdF.col(0);
  col(E_YOC) = -AdF.col(1);
  col(E_AOC) = -AdF.col(3);
  col(E_BOC) = -AdF.col(4);
  col(E_COC) = -Matrix6d::Identity().col(5); // Rz(−E_COC) at w: the same as a constant ε_zc
  // A axis line: S_A at Z, S_A⁻¹ at A; twist of S_A = (0, E_YOA, E_ZOA; 0, E_BOA, E_COA).
  col(E_YOA) = AdZ.col(1) - AdA.col(1);
  col(E_ZOA) = AdZ.col(2) - AdA.col(2);
  col(E_BOA) = AdZ.col(4) - AdA.col(4);
  col(E_COA) = AdZ.col(5) - AdA.col(5);
  col(E_AOA) = AdA.col(3); // the same as a constant ε_xa

  data.J_twistg_e = adjoint(data.wMg_ideal.inverse(Eigen::Isometry)) * J;
}

Vector6d twist_w_linear(const ErrorVector& e, const AxisPose& q) {
  const auto E = [&](ComponentId k) { return e(index(k)); };
  const IdealFrames f = ideal_frames(q);

  // Each frame's share of the error twist, the columns of error_jacobians summed with their values.
  Vector6d at_w = -motion_twist(e, Axis::C);
  at_w(5) -= E(E_COC);
  Vector6d at_F;
  at_F << -E(E_XOC), -E(E_YOC), 0.0, -E(E_AOC), -E(E_BOC), 0.0;
  Vector6d S_A;
  S_A << 0.0, E(E_YOA), E(E_ZOA), 0.0, E(E_BOA), E(E_COA);
  Vector6d at_Z = motion_twist(e, Axis::Z) + S_A;
  at_Z(0) -= q.z * E(S_xz);
  Vector6d at_A = motion_twist(e, Axis::A) - S_A;
  at_A(3) += E(E_AOA);
  Vector6d at_g = motion_twist(e, Axis::Y);
  at_g(0) -= q.y * E(S_xy);
  at_g(2) -= q.y * E(S_zy);
  return at_w + transport(f.wMF, at_F) + transport(f.wMX, motion_twist(e, Axis::X)) + transport(f.wMZ, at_Z) +
         transport(f.wMA, at_A) + transport(f.wMg, at_g);
}

PoseErrorTwists twist_linear(const ErrorVector& e, const AxisPose& q, MachineData& data) {
  error_jacobians(q, data);
  return {data.J_twistw_e * e, data.J_twistg_e * e};
}

PoseErrorTwists twist_linear(const MachineModel& model, MachineData& data, const AxisPose& q) {
  model.errors_at(q, data.e);
  return twist_linear(data.e, q, data);
}

} // namespace geartopo::machine
