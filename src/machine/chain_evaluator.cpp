// geartopo — the cached evaluator of a chain described as data (chain_evaluator.hpp). Units: mm, rad.
#include "geartopo/machine/chain_evaluator.hpp"

#include "geartopo/machine/chain_kinematics.hpp" // errors_at

#include "chain_joints.hpp"

#include <bit>

namespace geartopo::machine {

namespace {

/// Same bits: a cached value computed at `cached` is the value at `now` (NaN included, −0 ≠ +0).
bool same(double cached, double now) {
  return std::bit_cast<std::uint64_t>(cached) == std::bit_cast<std::uint64_t>(now);
}

/// out = a·b for isometries, written in place: out's last row stays (0, 0, 0, 1) from its set-up, and no 4×4
/// temporary is copied (the copies cost as much as the product).
void multiply_into(const Pose& a, const Pose& b, Pose& out) {
  out.linear().noalias() = a.linear() * b.linear();
  out.translation().noalias() = a.linear() * b.translation();
  out.translation() += a.translation();
}

/// out = joint j as it enters wMg (detail::chain_joint), the workpiece side's inverse written in place as
/// [Rᵀ | −Rᵀ·p]: out's last row stays (0, 0, 0, 1) from its set-up.
void joint_into(const Joint& j, const ErrorVector& e, double theta, const Pose& S, const Pose& S_inverse, Pose& out) {
  const Pose M = detail::exact_joint(j, e, theta, S, S_inverse);
  if (!j.workpiece_side) {
    out = M;
    return;
  }
  out.linear().noalias() = M.linear().transpose();
  out.translation().noalias() = -(out.linear() * M.translation());
}

/// Binds `data` to the chain and the model, all components evaluated at θ, when it holds another's (or nothing);
/// else re-evaluates the motion components of the axes that moved (the others are the same bits as a fresh
/// MachineModel::errors_at: constants never change, and an axis' components are a function of its position alone).
void refresh_errors(const KinematicChain& chain, const MachineModel& model, ChainData& data, const AxisValues& theta) {
  if (data.chain != &chain || data.model_id != model.id()) {
    data.chain = &chain;
    data.model_id = model.id();
    errors_at(model, theta, data.e);
    data.theta_e = theta.v;
    for (std::size_t i = 0; i < kAxisCount; ++i) {
      const Joint& j = chain.joints()[i];
      if (j.kind != AxisKind::Rotary) continue;
      data.S[i] = detail::axis_line(j, data.e);
      data.S_inverse[i] = data.S[i].inverse(Eigen::Isometry);
    }
    for (Pose& tail : data.wMg_tail) tail.setIdentity();
    for (Pose& joint : data.joint) joint.setIdentity();
    data.pose_ready = data.twist_ready = false;
    return;
  }
  for (int slot = 0; slot < kAxisCount; ++slot) {
    if (same(data.theta_e(slot), theta.v(slot))) continue;
    model.axis_errors_at(static_cast<Axis>(slot), theta.v(slot), data.e);
    data.theta_e(slot) = theta.v(slot);
  }
}

/// The last joint (chain order) whose position differs from `cached`, −1 if none; every joint when not `ready`.
int last_moved(const KinematicChain& chain, const std::array<double, kAxisCount>& cached, bool ready,
               const AxisValues& theta) {
  if (!ready) return kAxisCount - 1;
  for (int i = kAxisCount - 1; i >= 0; --i)
    if (!same(cached[static_cast<std::size_t>(i)], theta[chain.joints()[static_cast<std::size_t>(i)].slot])) return i;
  return -1;
}

/// Joint j's error twist ξ in its parent frame: the columns of error_jacobians for its components
/// (chain_kinematics.cpp, linear_columns / rotary_columns) summed with their values.  6×1
///   linear: (δ + p × ε − θ·Σ_k S_k·lean_k; ε), p = o + θ·d
///   rotary: Ad(T(o))·(Ad(R)·((δ; ε) − u) + u + (0; E_0·d)), u the axis line's twist (no −Ad(R)·u on the spindle)
Vector6d joint_error_twist(const Joint& j, const ErrorVector& e, double theta, const Eigen::Matrix3d& R) {
  const Eigen::Vector3d delta = detail::v3(e, j.motion), eps = detail::v3(e, j.motion + 3);
  Vector6d xi;
  if (j.kind == AxisKind::Linear) {
    Eigen::Vector3d p = j.offset;
    p(j.dir) += j.sign * theta;
    Eigen::Vector3d v = delta + p.cross(eps);
    for (int k = 0; k < j.squareness_count; ++k)
      v += (-(theta * e(j.squareness[static_cast<std::size_t>(k)]))) * j.lean[static_cast<std::size_t>(k)];
    xi << v, eps;
    return xi;
  }
  const Vector6d u = detail::axis_line_twist(j, e);
  Vector6d moved;
  moved << delta, eps;
  if (!j.carries_workpiece) moved -= u;
  xi.head<3>() = R * moved.head<3>();
  xi.tail<3>() = R * moved.tail<3>();
  xi += u;
  xi(3 + j.dir) += j.sign * e(j.location + 4);
  xi.head<3>() += j.offset.cross(xi.tail<3>());
  return xi;
}

} // namespace

const Pose& actual_wMg(const KinematicChain& chain, const MachineModel& model, ChainData& data,
                       const AxisValues& theta) {
  refresh_errors(chain, model, data, theta);
  const int last = last_moved(chain, data.theta_pose, data.pose_ready, theta);
  for (int i = last; i >= 0; --i) {
    const auto k = static_cast<std::size_t>(i);
    const Joint& j = chain.joints()[k];
    if (!data.pose_ready || !same(data.theta_pose[k], theta[j.slot])) {
      joint_into(j, data.e, theta[j.slot], data.S[k], data.S_inverse[k], data.joint[k]);
      data.theta_pose[k] = theta[j.slot];
    }
    if (i == kAxisCount - 1) data.wMg_tail[k] = data.joint[k];
    else multiply_into(data.joint[k], data.wMg_tail[k + 1], data.wMg_tail[k]);
  }
  data.pose_ready = true;
  return data.wMg_tail[0];
}

const Vector6d& twist_w_linear(const KinematicChain& chain, const MachineModel& model, ChainData& data,
                               const AxisValues& theta) {
  refresh_errors(chain, model, data, theta);
  const int last = last_moved(chain, data.theta_twist, data.twist_ready, theta);
  for (int i = last; i >= 0; --i) {
    const auto k = static_cast<std::size_t>(i);
    const Joint& j = chain.joints()[k];
    if (!data.twist_ready || !same(data.theta_twist[k], theta[j.slot])) {
      const double t = theta[j.slot];
      const Pose M = detail::ideal_joint(j, t);
      const Vector6d xi = joint_error_twist(j, data.e, t, M.linear()); // a rotary joint's turn R_d(s·θ), else I
      // Workpiece side: the factor is M⁻¹, whose error twist is −Ad(M⁻¹)·ξ in the frame before it.
      data.ideal[k] = j.workpiece_side ? M.inverse(Eigen::Isometry) : M;
      data.local_twist[k] = j.workpiece_side ? Vector6d(-detail::transport(data.ideal[k], xi)) : xi;
      data.theta_twist[k] = t;
    }
    data.twist_tail[k] = data.local_twist[k];
    if (i < kAxisCount - 1) data.twist_tail[k] += detail::transport(data.ideal[k], data.twist_tail[k + 1]);
  }
  data.twist_ready = true;
  return data.twist_tail[0];
}

} // namespace geartopo::machine
