// geartopo — exact and first-order wheel pose of a chain described as data (chain_kinematics.hpp). Units: mm, rad.
#include "geartopo/machine/chain_kinematics.hpp"

#include "chain_joints.hpp"

namespace geartopo::machine {

namespace {

using detail::ChainFrames;

Vector6d translation_twist(const Eigen::Vector3d& v) {
  Vector6d t = Vector6d::Zero();
  t.head<3>() = v;
  return t;
}
Vector6d rotation_twist(const Eigen::Vector3d& w) {
  Vector6d t = Vector6d::Zero();
  t.tail<3>() = w;
  return t;
}

/// Transports ξ (in joint i's parent frame) to w as the factor of joint i enters wMg.
Vector6d to_w(const ChainFrames& f, int i, bool workpiece_side, const Vector6d& xi) {
  return workpiece_side ? Vector6d(-(adjoint(f.frame[static_cast<std::size_t>(i + 1)]) * xi))
                        : Vector6d(adjoint(f.frame[static_cast<std::size_t>(i)]) * xi);
}

/// The unit twists of a linear joint's components at e = 0, in its parent frame: J = T(o + θ·d + δ − θ·S·lean)·R(ε).
void linear_columns(const Joint& j, double theta, const ChainFrames& f, int i, Matrix6E& J) {
  Eigen::Vector3d p = j.offset;
  p(j.dir) += j.sign * theta;
  for (int c = 0; c < 3; ++c) {
    J.col(j.motion + c) = to_w(f, i, j.workpiece_side, translation_twist(Eigen::Vector3d::Unit(c)));
    // A rotation R(ε) after T(p): Ad(T(p))·(0; e_c) = (p × e_c; e_c).
    Vector6d r;
    r << p.cross(Eigen::Vector3d::Unit(c)), Eigen::Vector3d::Unit(c);
    J.col(j.motion + 3 + c) = to_w(f, i, j.workpiece_side, r);
  }
  for (int k = 0; k < j.squareness_count; ++k)
    J.col(j.squareness[static_cast<std::size_t>(k)]) =
        to_w(f, i, j.workpiece_side, translation_twist(-theta * j.lean[static_cast<std::size_t>(k)]));
}

/// The same for a rotary joint: J = T(o)·S·R_d(s·(θ + E_0))·E(δ, ε)·S⁻¹ (no S⁻¹ on the workpiece spindle).
void rotary_columns(const Joint& j, double theta, const ChainFrames& f, int i, Matrix6E& J) {
  const Pose To = translation(j.offset);
  const Pose TR = To * detail::coordinate_turn(j.dir, j.sign * theta);
  const Matrix6d Ad_TR = adjoint(TR), Ad_To = adjoint(To);
  for (int c = 0; c < 3; ++c) {
    J.col(j.motion + c) = to_w(f, i, j.workpiece_side, Ad_TR * translation_twist(Eigen::Vector3d::Unit(c)));
    J.col(j.motion + 3 + c) = to_w(f, i, j.workpiece_side, Ad_TR * rotation_twist(Eigen::Vector3d::Unit(c)));
  }
  J.col(j.location + 4) =
      to_w(f, i, j.workpiece_side, Ad_To * rotation_twist(j.sign * Eigen::Vector3d::Unit(j.dir)));
  const Matrix6d Ad_R = adjoint(detail::coordinate_turn(j.dir, j.sign * theta));
  for (int l = 0; l < 4; ++l) {
    ErrorVector unit = ErrorVector::Zero();
    unit(j.location + l) = 1.0;
    const Vector6d u = detail::axis_line_twist(j, unit);
    // S·R·S⁻¹ moves the turn's axis line: d(S·R·S⁻¹)·(S·R·S⁻¹)⁻¹ = u − Ad(R)·u at S = I.
    const Vector6d xi = j.carries_workpiece ? u : Vector6d(u - Ad_R * u);
    J.col(j.location + l) = to_w(f, i, j.workpiece_side, Ad_To * xi);
  }
}

} // namespace

Pose actual_wMg(const KinematicChain& chain, const ErrorVector& e, const AxisValues& theta) {
  Pose M = Pose::Identity();
  for (const Joint& j : chain.joints()) {
    Pose S = Pose::Identity();
    if (j.kind == AxisKind::Rotary) S = detail::axis_line(j, e);
    M = M * detail::chain_joint(j, e, theta[j.slot], S, S.inverse(Eigen::Isometry));
  }
  return M;
}

PoseErrorTwists exact_pose_error(const KinematicChain& chain, const ErrorVector& e, const AxisValues& theta) {
  const Pose ideal = chain.ideal_wMg(theta);
  const Pose actual = actual_wMg(chain, e, theta);
  return {pose_error_twist(actual * ideal.inverse(Eigen::Isometry)),
          pose_error_twist(ideal.inverse(Eigen::Isometry) * actual)};
}

void error_jacobians(const KinematicChain& chain, const AxisValues& theta, Matrix6E& J_twistw_e, Matrix6E& J_twistg_e) {
  const ChainFrames f = detail::chain_frames(chain, theta);
  J_twistw_e.setZero();
  for (int i = 0; i < kAxisCount; ++i) {
    const Joint& j = chain.joints()[static_cast<std::size_t>(i)];
    if (j.kind == AxisKind::Linear) linear_columns(j, theta[j.slot], f, i, J_twistw_e);
    else rotary_columns(j, theta[j.slot], f, i, J_twistw_e);
  }
  J_twistg_e = adjoint(f.frame[kAxisCount].inverse(Eigen::Isometry)) * J_twistw_e;
}

Matrix65 J_twistw_theta(const KinematicChain& chain, const AxisValues& theta) {
  const ChainFrames f = detail::chain_frames(chain, theta);
  Matrix65 J = Matrix65::Zero();
  for (int i = 0; i < kAxisCount; ++i) {
    const Joint& j = chain.joints()[static_cast<std::size_t>(i)];
    const Eigen::Vector3d d = j.sign * Eigen::Vector3d::Unit(j.dir);
    // Linear: a translation along d (an offset does not move it); rotary: a turn about d through the offset point.
    const Vector6d xi = j.kind == AxisKind::Linear ? translation_twist(d)
                                                   : Vector6d(adjoint(translation(j.offset)) * rotation_twist(d));
    J.col(static_cast<int>(j.slot)) = to_w(f, i, j.workpiece_side, xi);
  }
  return J;
}

Matrix65 J_twistg_theta(const KinematicChain& chain, const AxisValues& theta) {
  return adjoint(chain.ideal_wMg(theta).inverse(Eigen::Isometry)) * J_twistw_theta(chain, theta);
}

} // namespace geartopo::machine
