// geartopo tests — the first-order model is the linearisation of the exact chain: the difference is O(s²).
// Units: mm, rad.
#include "test_helpers.hpp"

#include "geartopo/machine/first_order.hpp"

#include <gtest/gtest.h>

namespace geartopo::machine {
namespace {

using test::random_errors;
using test::random_pose;

double max_abs(const Vector6d& v) { return v.cwiseAbs().maxCoeff(); }

TEST(FirstOrder, DifferenceToTheExactChainIsSecondOrder) {
  std::mt19937 rng(21);
  MachineData data;
  for (int trial = 0; trial < 50; ++trial) {
    const AxisPose q = random_pose(rng);
    const ErrorVector e = random_errors(rng);
    double diff_w[2], diff_g[2];
    for (int k = 0; k < 2; ++k) {
      const double s = k == 0 ? 1.0 : 0.5;
      const PoseErrorTwists ex = exact_pose_error(s * e, q, data);
      const PoseErrorTwists lin = twist_linear(s * e, q, data);
      diff_w[k] = max_abs(ex.w - lin.w);
      diff_g[k] = max_abs(ex.g - lin.g);
      // The first-order model captures nearly everything: the residual is ~ε·(error) relative.
      EXPECT_LT(diff_w[k], 2e-3 * max_abs(ex.w));
      EXPECT_LT(diff_g[k], 2e-3 * max_abs(ex.g));
    }
    // Halving every error quarters the difference.
    EXPECT_GE(diff_w[0] / diff_w[1], 3.5) << "trial " << trial;
    EXPECT_LE(diff_w[0] / diff_w[1], 4.5) << "trial " << trial;
    EXPECT_GE(diff_g[0] / diff_g[1], 3.5) << "trial " << trial;
    EXPECT_LE(diff_g[0] / diff_g[1], 4.5) << "trial " << trial;
  }
}

TEST(FirstOrder, SameWithAModelBuiltFromTablesAndConstants) {
  // Model path: the errors come from the sources at q; scaling the sources scales the errors.
  std::mt19937 rng(22);
  const AxisPose q{610.0, -35.0, 420.0, 0.45, 2.2};
  const ErrorVector e = random_errors(rng);
  double diff[2];
  for (int k = 0; k < 2; ++k) {
    const double s = k == 0 ? 1.0 : 0.5;
    std::vector<ErrorSource> sources;
    for (int i = 0; i < kComponentCount; ++i) {
      const ComponentInfo& c = info(component_at(i));
      const double file_value = s * e(i) / (c.quantity == Quantity::Length ? 1e-3 : 1e-6);
      sources.push_back(ErrorSource::constant(c.id, file_value, file_unit(c.quantity)));
    }
    const MachineModel model(Strokes::skmc_1200w(), std::move(sources));
    MachineData data;
    const PoseErrorTwists ex = exact_pose_error(model, data, q);
    const PoseErrorTwists lin = twist_linear(model, data, q);
    diff[k] = max_abs(ex.w - lin.w);
  }
  EXPECT_GE(diff[0] / diff[1], 3.5);
  EXPECT_LE(diff[0] / diff[1], 4.5);
}

TEST(FirstOrder, FrameRelationOfTheTwoTwists) {
  // twist_w = Ad(wMg)·twist_g holds exactly for the linear model and to first order for the exact one.
  std::mt19937 rng(23);
  MachineData data;
  const AxisPose q = random_pose(rng);
  const ErrorVector e = random_errors(rng);
  const PoseErrorTwists lin = twist_linear(e, q, data);
  EXPECT_LT(max_abs(adjoint(ideal_wMg(q)) * lin.g - lin.w), 1e-12);
  const PoseErrorTwists ex = exact_pose_error(e, q, data);
  EXPECT_LT(max_abs(adjoint(ideal_wMg(q)) * ex.g - ex.w), 1e-3 * max_abs(ex.w));
}

TEST(FirstOrder, WorkpieceTwistWithoutTheJacobianEqualsJTimesE) {
  // twist_w_linear groups the same columns per frame; only rounding may differ. Each component alone too, so a
  // component moved to the wrong frame or sign cannot hide behind the others.
  std::mt19937 rng(29);
  MachineData data;
  for (int trial = 0; trial < 50; ++trial) {
    const AxisPose q = random_pose(rng);
    const ErrorVector e = random_errors(rng);
    const Vector6d reference = twist_linear(e, q, data).w;
    EXPECT_LT(max_abs(twist_w_linear(e, q) - reference), 1e-12 * (1.0 + max_abs(reference))) << "trial " << trial;
  }
  const AxisPose q = random_pose(rng);
  error_jacobians(q, data);
  for (int k = 0; k < kComponentCount; ++k) {
    ErrorVector unit = ErrorVector::Zero();
    unit(k) = 1.0;
    const Vector6d column = data.J_twistw_e.col(k);
    EXPECT_LT(max_abs(twist_w_linear(unit, q) - column), 1e-12 * (1.0 + max_abs(column))) << info(component_at(k)).name;
  }
}

} // namespace
} // namespace geartopo::machine
