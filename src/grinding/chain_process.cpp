// geartopo — the grinding process of a chain described as data (chain_process.hpp). Units: mm, rad.
#include "geartopo/grinding/chain_process.hpp"

#include "geartopo/machine/chain_evaluator.hpp"
#include "geartopo/machine/chain_kinematics.hpp"
#include "geartopo/machine/transforms.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace geartopo::grinding {

namespace {

// One evaluator scratch per thread keeps the process shareable between threads (const model, mutable data). It holds
// the joints that did not move since the thread's last point (along a stroke: all but the spindle and the stroke
// axes); its results do not depend on what it held (machine/chain_evaluator.hpp), so neither on the thread count.
machine::ChainData& thread_data() {
  thread_local machine::ChainData data;
  return data;
}

} // namespace

machine::AxisValues ChainProcess::machine_axes(const PathPoint& pp) const {
  machine::AxisPose q = pp.q;
  q.z += z0_;
  return chain_.axes(q);
}

void ChainProcess::check_path(const WheelPath& path, double step_mm) const {
  for (const PathPoint& pp : path.sample(step_mm)) {
    machine::AxisPose q = pp.q;
    q.z += z0_;
    const machine::InverseKinematics ik = chain_.solve(q);
    const std::string where = fmt::format("{} chain, space {}, Z = {:.3f} mm", chain_.name(), pp.space, pp.z_stroke_mm);
    if (!(std::abs(ik.linear_det) >= machine::kSingularDet))
      throw std::runtime_error(fmt::format("{}: the linear axes are singular there (det = {:.2e}: they cannot move the "
                                           "wheel centre in every direction)", where, ik.linear_det));
    if (const auto v = chain_.outside_stroke(ik.theta)) throw std::runtime_error(where + ": " + v->message);
  }
}

machine::Pose ChainProcess::actual_wMg(const PathPoint& pp) const {
  machine::Pose wMg = machine::actual_wMg(chain_, model_, thread_data(), machine_axes(pp));
  wMg.translation().z() -= z0_; // Tz(−z₀)·cMg
  return wMg;
}

machine::Vector6d ChainProcess::error_twist_w(const PathPoint& pp) const {
  // The datum shift Tz(−z₀) is a pure translation along the gear axis: it moves the twist's point of reference.
  machine::Vector6d twist = machine::twist_w_linear(chain_, model_, thread_data(), machine_axes(pp));
  twist.head<3>() += Eigen::Vector3d(0.0, 0.0, -z0_).cross(twist.tail<3>());
  return twist;
}

} // namespace geartopo::grinding
