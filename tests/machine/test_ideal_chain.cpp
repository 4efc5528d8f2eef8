// geartopo tests — the ideal chain is Eq. 11, and the exact chain without errors is the ideal one.
// Units: mm, rad.
#include "test_helpers.hpp"

#include "geartopo/machine/first_order.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace geartopo::machine {
namespace {

using test::random_pose;

/// Eq. 11 built independently of the library: Rz(γ)⁻¹·Tx(x)·Tz(z)·Rx(α)·Ty(y) with Eigen's own primitives.
Eigen::Matrix4d chain_from_eigen(const AxisPose& q) {
  Eigen::Affine3d m = Eigen::Affine3d(Eigen::AngleAxisd(q.c, Eigen::Vector3d::UnitZ())).inverse() *
                      Eigen::Translation3d(q.x, 0, 0) * Eigen::Translation3d(0, 0, q.z) *
                      Eigen::AngleAxisd(q.a, Eigen::Vector3d::UnitX()) * Eigen::Translation3d(0, q.y, 0);
  return m.matrix();
}

TEST(IdealChain, ClosedFormOfEq11EqualsTheMatrixChainAt200RandomPoses) {
  std::mt19937 rng(11);
  MachineData data;
  for (int i = 0; i < 200; ++i) {
    const AxisPose q = random_pose(rng);
    const Eigen::Matrix4d closed = ideal_wMg(q).matrix();
    const Eigen::Matrix4d chain = chain_from_eigen(q);
    const Eigen::Matrix4d lib = ideal_kinematics(q, data).matrix();
    const double scale = 1.0 + std::abs(q.x) + std::abs(q.y) + std::abs(q.z); // translations are ~1000 mm
    EXPECT_LT((closed.topLeftCorner<3, 3>() - chain.topLeftCorner<3, 3>()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((closed.col(3) - chain.col(3)).cwiseAbs().maxCoeff(), 1e-12 * scale);
    EXPECT_LT((lib - chain).cwiseAbs().maxCoeff(), 1e-12 * scale);
  }
}

TEST(IdealChain, GeometryOfTheAxes) {
  constexpr double deg = std::numbers::pi / 180.0;
  // γ = 0: the wheel centre sits at (x, y·cosα, z + y·sinα) and its spindle axis (g's y) is (0, cosα, sinα).
  const AxisPose q{300.0, 20.0, 50.0, 30.0 * deg, 0.0};
  const Pose m = ideal_wMg(q);
  EXPECT_NEAR((m.translation() - Eigen::Vector3d(300.0, 20.0 * std::cos(q.a), 50.0 + 20.0 * std::sin(q.a))).norm(), 0.0, 1e-12);
  EXPECT_NEAR((m.linear().col(1) - Eigen::Vector3d(0.0, std::cos(q.a), std::sin(q.a))).norm(), 0.0, 1e-15);
  // +C turns the workpiece by +γ about z: seen from the workpiece the wheel turns by −γ.
  const AxisPose qc{300.0, 0.0, 0.0, 0.0, 90.0 * deg};
  EXPECT_NEAR((ideal_wMg(qc).translation() - Eigen::Vector3d(0.0, -300.0, 0.0)).norm(), 0.0, 1e-12);
}

TEST(IdealChain, ExactChainWithoutErrorsIsIdealAndTwistsVanish) {
  std::mt19937 rng(12);
  const MachineModel model(Strokes::skmc_1200w());
  MachineData data;
  for (int i = 0; i < 100; ++i) {
    AxisPose q = random_pose(rng);
    q.x = std::min(q.x, 900.0);
    const Pose actual = actual_wMg(model, data, q);
    EXPECT_LT((actual.matrix() - ideal_wMg(q).matrix()).cwiseAbs().maxCoeff(), 1e-12 * 2000.0);
    const PoseErrorTwists ex = exact_pose_error(model, data, q);
    EXPECT_LT(ex.w.cwiseAbs().maxCoeff(), 1e-12 * 2000.0);
    EXPECT_LT(ex.g.cwiseAbs().maxCoeff(), 1e-12 * 2000.0);
    const PoseErrorTwists lin = twist_linear(model, data, q);
    EXPECT_EQ(lin.w.cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(lin.g.cwiseAbs().maxCoeff(), 0.0);
  }
}

} // namespace
} // namespace geartopo::machine
