// geartopo — the wheel pose and the first-order error twist of a chain described as data, point after point along a
// path, recomputing only what moved (issue 42's speed target; docs/performance.md, ChainPoint).
//
// Pinocchio's split: the model is const (the KinematicChain and the MachineModel), the scratch is a ChainData the
// caller owns (one per thread). Along a grinding stroke only the spindle and the stroke axis (or axes) move; the
// other joints, their error components and the products of the joints that follow them stay in the ChainData.
//   exact pose:   wMg = J_0·(J_1·(J_2·(J_3·J_4)))         the joints multiplied from the wheel end, so a tail of
//                                                       joints standing still is one cached product
//   first order:  ξ_w = c_0 + Ad(N_0)·(c_1 + Ad(N_1)·(c_2 + …))   one backward pass (Pinocchio's backward sweep):
//                 N_i the ideal joint as it enters wMg, c_i joint i's error twist in the frame before it
//                 (tool side: ξ_i, the columns of error_jacobians for joint i summed with their values; workpiece
//                 side: −Ad(N_i)·ξ_i), instead of the 6×43 Jacobian times e.
// Every cached quantity is a fixed function of its own joint's position (its bits) and of the constants, and the
// association above never changes: the result at θ has the same bits whatever the ChainData held before (results
// identical at any thread count), and equals the uncached actual_wMg / error_jacobians (chain_kinematics.hpp) to
// rounding (tests/machine/test_chain_cache.cpp). No heap allocation.
// Units: mm, rad.
#pragma once

#include "geartopo/machine/kinematic_chain.hpp"
#include "geartopo/machine/machine_model.hpp"

#include <array>
#include <cstdint>

namespace geartopo::machine {

/// The scratch of the cached chain evaluator: valid for one chain and one machine model at a time (rebound, and
/// everything recomputed, when asked about another). Arrays over joints are in chain order (KinematicChain::joints).
struct ChainData {
  const KinematicChain* chain = nullptr; ///< the chain it holds values of (chains live until the program ends)
  std::uint64_t model_id = 0;            ///< the MachineModel it holds values of (MachineModel::id)
  ErrorVector e = ErrorVector::Zero();   ///< components at the axis positions theta_e (constants once), 43×1
  Vector5d theta_e = Vector5d::Zero();   ///< positions of e's motion components, pose order (mm, rad)
  std::array<Pose, kAxisCount> S, S_inverse; ///< rotary joints' actual axis lines and their inverses (constants)

  bool pose_ready = false;                   ///< joint, wMg_tail hold values (for theta_pose)
  std::array<double, kAxisCount> theta_pose{}; ///< each joint's position when its entries below were computed
  std::array<Pose, kAxisCount> joint;        ///< actual joint i as it enters wMg (inverted on the workpiece side)
  std::array<Pose, kAxisCount> wMg_tail;     ///< joint[i]·joint[i+1]⋯joint[4]; wMg_tail[0] = wMg

  bool twist_ready = false;                    ///< ideal, local_twist, twist_tail hold values (for theta_twist)
  std::array<double, kAxisCount> theta_twist{};
  std::array<Pose, kAxisCount> ideal;          ///< ideal joint i as it enters wMg (N_i)
  std::array<Vector6d, kAxisCount> local_twist; ///< c_i, in the frame before joint i, 6×1
  std::array<Vector6d, kAxisCount> twist_tail;  ///< c_i + Ad(N_i)·twist_tail[i+1], in the frame before joint i (w: [0])
};

/// The exact wheel pose at θ with the model's components at θ: actual_wMg(chain, e(θ), θ) to rounding.  wMg
const Pose& actual_wMg(const KinematicChain& chain, const MachineModel& model, ChainData& data,
                       const AxisValues& theta);

/// The first-order pose-error twist in w at θ with the model's components at θ: J_twistw_e(θ)·e(θ) to rounding.  6×1
const Vector6d& twist_w_linear(const KinematicChain& chain, const MachineModel& model, ChainData& data,
                               const AxisValues& theta);

} // namespace geartopo::machine
