// geartopo — ideal and actual Jacobians J_twist*_q by adjoint transport of each joint's body rate.
// Units: mm, rad.
#include "geartopo/machine/jacobian.hpp"

#include "geartopo/machine/transforms.hpp"

namespace geartopo::machine {

namespace {

using enum ComponentId;

Vector6d twist(const Eigen::Vector3d& v, const Eigen::Vector3d& w) {
  Vector6d t;
  t << v, w;
  return t;
}

Eigen::Vector3d triple(const ErrorVector& e, ComponentId a, ComponentId b, ComponentId c) {
  return {e(index(a)), e(index(b)), e(index(c))};
}

/// Body rate vee(E⁻¹ dE/dq) of E = T(δ(q))·R(ε(q)): (Rᵀδ'; ω_body).
Vector6d error_body_rate(const Eigen::Vector3d& eps, const Eigen::Vector3d& ddelta, const Eigen::Vector3d& deps) {
  return twist(error_rotation(eps).transpose() * ddelta, error_rotation_body_rate(eps, deps));
}

} // namespace

Matrix65 J_twistw_q(const AxisPose& q) {
  // Each joint's unit motion is a fixed twist in its own frame, transported to w by the ideal sub-chain:
  //   X: e_x translation in F/X, Z: e_z translation in X/Z, A: e_x rotation in Z/A, Y: e_y translation in A/g,
  //   C: wMF = Rz(−γ), so dγ turns the wheel by −e_z about the origin of w.
  const IdealFrames f = ideal_frames(q);
  Matrix65 J;
  J.col(static_cast<int>(Axis::X)) = adjoint(f.wMX).col(0);
  J.col(static_cast<int>(Axis::Y)) = adjoint(f.wMg).col(1);
  J.col(static_cast<int>(Axis::Z)) = adjoint(f.wMZ).col(2);
  J.col(static_cast<int>(Axis::A)) = adjoint(f.wMA).col(3);
  J.col(static_cast<int>(Axis::C)) = -Matrix6d::Identity().col(5);
  return J;
}

Matrix65 J_twistg_q(const AxisPose& q) {
  return adjoint(ideal_wMg(q).inverse(Eigen::Isometry)) * J_twistw_q(q);
}

void actual_jacobians(const MachineModel& model, MachineData& data, const AxisPose& q) {
  actual_wMg(model, data, q);
  model.error_rates_at(q, data.de);
  const ErrorVector& e = data.e;
  const ErrorVector& d = data.de;
  const auto E = [&](ComponentId k) { return e(index(k)); };
  const auto D = [&](ComponentId k) { return d(index(k)); };
  Matrix65& J = data.J_twistw_q;

  // C: M = FMC = S_C·Rz(γ+E_COC)·E_C, wMF = M⁻¹. vee(M⁻¹dM) = Ad(E_C⁻¹)·e_ωz + rate(E_C); the spatial rate of
  // M⁻¹ in w is −vee(M⁻¹dM) (w is M's child frame).
  {
    const Eigen::Vector3d eps = triple(e, epsilon_xc, epsilon_yc, epsilon_zc);
    const Pose Ec = error_htm(triple(e, delta_xc, delta_yc, delta_zc), eps);
    const Vector6d rate = adjoint(Ec.inverse(Eigen::Isometry)).col(5) +
                          error_body_rate(eps, triple(d, delta_xc, delta_yc, delta_zc), triple(d, epsilon_xc, epsilon_yc, epsilon_zc));
    J.col(static_cast<int>(Axis::C)) = -rate;
  }
  // X: FMX = [R(ε_x) | (x + δ_xx, δ_yx, δ_zx)].
  {
    const Eigen::Vector3d eps = triple(e, epsilon_xx, epsilon_yx, epsilon_zx);
    const Eigen::Vector3d dp(1.0 + D(delta_xx), D(delta_yx), D(delta_zx));
    J.col(static_cast<int>(Axis::X)) =
        adjoint(data.wMX) * error_body_rate(eps, dp, triple(d, epsilon_xx, epsilon_yx, epsilon_zx));
  }
  // Z: XMZ = [R(ε_z) | (δ_xz − z·S_xz, δ_yz, z + δ_zz)].
  {
    const Eigen::Vector3d eps = triple(e, epsilon_xz, epsilon_yz, epsilon_zz);
    const Eigen::Vector3d dp(D(delta_xz) - E(S_xz), D(delta_yz), 1.0 + D(delta_zz));
    J.col(static_cast<int>(Axis::Z)) =
        adjoint(data.wMZ) * error_body_rate(eps, dp, triple(d, epsilon_xz, epsilon_yz, epsilon_zz));
  }
  // A: ZMA = S_A·Rx(α+E_AOA)·E_A·S_A⁻¹: vee(ZMA⁻¹ dZMA) = Ad(S_A)·(Ad(E_A⁻¹)·e_ωx + rate(E_A)).
  {
    const Eigen::Vector3d eps = triple(e, epsilon_xa, epsilon_ya, epsilon_za);
    const Pose Ea = error_htm(triple(e, delta_xa, delta_ya, delta_za), eps);
    const Pose S_A = translation(0.0, E(E_YOA), E(E_ZOA)) * Ry(E(E_BOA)) * Rz(E(E_COA));
    const Vector6d rate = adjoint(Ea.inverse(Eigen::Isometry)).col(3) +
                          error_body_rate(eps, triple(d, delta_xa, delta_ya, delta_za), triple(d, epsilon_xa, epsilon_ya, epsilon_za));
    J.col(static_cast<int>(Axis::A)) = adjoint(data.wMA) * (adjoint(S_A) * rate);
  }
  // Y: AMY = [R(ε_y) | (δ_xy − y·S_xy, y + δ_yy, δ_zy − y·S_zy)].
  {
    const Eigen::Vector3d eps = triple(e, epsilon_xy, epsilon_yy, epsilon_zy);
    const Eigen::Vector3d dp(D(delta_xy) - E(S_xy), 1.0 + D(delta_yy), D(delta_zy) - E(S_zy));
    J.col(static_cast<int>(Axis::Y)) =
        adjoint(data.wMg) * error_body_rate(eps, dp, triple(d, epsilon_xy, epsilon_yy, epsilon_zy));
  }
  data.J_twistg_q = adjoint(data.wMg.inverse(Eigen::Isometry)) * J;
}

} // namespace geartopo::machine
