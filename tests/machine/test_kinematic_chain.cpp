// geartopo tests — the kinematic chain as data (issue 42): the CFXZAY described as data against the compiled-in
// chain, the general inverse kinematics against Eq. 11's closed form, the Jacobians against finite differences, the
// CAFXZY preset against homogeneous transforms written here, and bad descriptions refused.
// Units: mm, rad (µm and µrad where a tolerance says so).
#include "test_helpers.hpp"

#include "geartopo/machine/chain_kinematics.hpp"
#include "geartopo/machine/first_order.hpp"
#include "geartopo/machine/jacobian.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <string>
#include <numbers>

namespace geartopo::machine {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::vector<const KinematicChain*> chains() {
  return {&cfxzay(), chain_preset("CAFXZY"), chain_preset("CXFZAY")};
}

double pose_difference(const Pose& a, const Pose& b) {
  return std::max((a.translation() - b.translation()).cwiseAbs().maxCoeff(),
                  1000.0 * (a.linear() - b.linear()).cwiseAbs().maxCoeff()); // rotation entries × 1000 mm lever
}

TEST(KinematicChain, CfxzayNamesAreTodaysNames) {
  for (int k = 0; k < kComponentCount; ++k) {
    const ComponentInfo& now = info(component_at(k));
    const ComponentInfo& data = cfxzay().info(component_at(k));
    EXPECT_EQ(data.name, now.name) << k;
    EXPECT_EQ(data.symbol, now.symbol) << k;
    EXPECT_EQ(data.axis, now.axis) << k;
    EXPECT_EQ(data.quantity, now.quantity) << k;
    EXPECT_EQ(data.position_dependent, now.position_dependent) << k;
    EXPECT_EQ(data.meaning, now.meaning) << k; // diagnosis.json and the families say the chain's meanings
    EXPECT_EQ(cfxzay().component_from_name(now.name), component_at(k));
  }
  EXPECT_EQ(cfxzay().layout(), "CFXZAY");
  EXPECT_TRUE(cfxzay().is_setting_chain());
  EXPECT_FALSE(cfxzay().component_from_name("delta_xw"));
}

TEST(KinematicChain, CafxzyNamesFollowTheScheme) {
  const KinematicChain& c = *chain_preset("CAFXZY");
  EXPECT_EQ(c.layout(), "CAFXZY");
  EXPECT_FALSE(c.is_setting_chain());
  // Squareness: each linear axis to the linear axes before it from the workpiece: X, then Z, then Y.
  EXPECT_EQ(c.info(ComponentId::S_xy).name, "S_xy");
  EXPECT_EQ(c.info(ComponentId::S_zy).name, "S_zy");
  EXPECT_EQ(c.info(ComponentId::S_xz).name, "S_xz");
  EXPECT_TRUE(c.on_workpiece_side(Axis::A));
  EXPECT_FALSE(c.on_workpiece_side(Axis::X));
}

// The CFXZAY described as data, evaluated joint by joint (chain_joints.hpp), gives the compiled-in chain's pose
// (chain.cpp, Eq. 22) for errors of every size up to 1 mm / 1 mrad at random poses.
TEST(KinematicChain, CfxzayAsDataIsTheCompiledInChain) {
  std::mt19937 rng(42);
  MachineData data;
  for (int trial = 0; trial < 50; ++trial) {
    const AxisPose q = test::random_pose(rng);
    const ErrorVector e = test::random_errors(rng) * (trial % 2 == 0 ? 1.0 : 20.0);
    const Pose compiled = actual_kinematics(e, q, data);
    const Pose described = actual_wMg(cfxzay(), e, AxisValues{q.vector()});
    EXPECT_LT(pose_difference(compiled, described), 1e-10) << trial; // 1e-4 µm
  }
}

TEST(KinematicChain, CfxzayAsDataHasTheCompiledInJacobians) {
  std::mt19937 rng(43);
  MachineData data;
  Matrix6E Jw, Jg;
  for (int trial = 0; trial < 20; ++trial) {
    const AxisPose q = test::random_pose(rng);
    const AxisValues theta{q.vector()};
    error_jacobians(q, data);
    error_jacobians(cfxzay(), theta, Jw, Jg);
    EXPECT_LT((Jw - data.J_twistw_e).cwiseAbs().maxCoeff(), 1e-12 * 2000.0) << trial;
    EXPECT_LT((Jg - data.J_twistg_e).cwiseAbs().maxCoeff(), 1e-12 * 2000.0) << trial;
    EXPECT_LT((J_twistw_theta(cfxzay(), theta) - J_twistw_q(q)).cwiseAbs().maxCoeff(), 1e-12 * 2000.0) << trial;
    EXPECT_LT((J_twistg_theta(cfxzay(), theta) - J_twistg_q(q)).cwiseAbs().maxCoeff(), 1e-12 * 2000.0) << trial;
  }
}

// Eq. 11's closed form for the CFXZAY: the axes ARE the setting, X = x, Y = y, Z = z, A = α, C = γ. The general
// solver (two turns from the orientation, a 3×3 solve for the wheel centre) must find exactly that, with the
// determinant of the linear axes' directions ±cos α (Y rides on the swivel).
TEST(KinematicChain, GeneralInverseKinematicsGivesEq11OnTheCfxzay) {
  std::mt19937 rng(44);
  for (int trial = 0; trial < 100; ++trial) {
    const AxisPose q = test::random_pose(rng);
    const InverseKinematics ik = cfxzay().solve(q);
    EXPECT_LT((ik.theta.v - q.vector()).head<3>().cwiseAbs().maxCoeff(), 1e-10) << trial;
    EXPECT_LT((ik.theta.v - q.vector()).tail<2>().cwiseAbs().maxCoeff(), 1e-15) << trial;
    EXPECT_NEAR(std::abs(ik.linear_det), std::cos(q.a), 1e-12);
    EXPECT_EQ(cfxzay().axes(q).v, q.vector()); // the preset's shortcut: exactly the setting
  }
}

// Every chain: the axes found put the wheel where Eq. 11 puts it, and the forward kinematics gives the setting back.
TEST(KinematicChain, InverseKinematicsReachesEq11OnEveryChain) {
  std::mt19937 rng(45);
  for (const KinematicChain* chain : chains()) {
    for (int trial = 0; trial < 50; ++trial) {
      const AxisPose q = test::random_pose(rng);
      const AxisValues theta = chain->solve(q).theta;
      EXPECT_LT(pose_difference(chain->ideal_wMg(theta), ideal_wMg(q)), 1e-10) << chain->name() << " " << trial;
      // The setting back, the turn γ modulo a full turn (setting() gives it in [0, 2π)).
      Vector5d back = chain->setting(theta).vector() - q.vector();
      back(4) = std::remainder(back(4), 2.0 * std::numbers::pi);
      EXPECT_LT(back.cwiseAbs().maxCoeff(), 1e-10) << chain->name() << " " << trial;
    }
  }
}

/// Central differences at h and h/2 against J: the error falls fourfold (O(h²): the Jacobian is the derivative, not a
/// near miss) and ends below 2·10⁻⁶ (mm or rad per unit; levers reach ~1000 mm).
void expect_converges(const Eigen::MatrixXd& J, const std::function<Eigen::MatrixXd(double)>& fd, double h,
                      const std::string& what) {
  const double coarse = (fd(h) - J).cwiseAbs().maxCoeff(), fine = (fd(h / 2) - J).cwiseAbs().maxCoeff();
  EXPECT_GT(fine / coarse, 0.2) << what;
  EXPECT_LT(fine / coarse, 0.3) << what;
  EXPECT_LT(fine, 2e-6) << what;
}

// Central differences of the exact chain in each component and each axis.
TEST(KinematicChain, JacobiansMatchFiniteDifferencesOnEveryChain) {
  std::mt19937 rng(46);
  for (const KinematicChain* chain : chains()) {
    for (int trial = 0; trial < 5; ++trial) {
      const AxisValues theta = chain->solve(test::random_pose(rng)).theta;
      const std::string what = chain->name() + " trial " + std::to_string(trial);
      Matrix6E Jw, Jg;
      error_jacobians(*chain, theta, Jw, Jg);
      // One component at a time, ±h, in the exact chain.
      const auto of_e = [&](const Eigen::VectorXd& e) { return actual_wMg(*chain, ErrorVector(e), theta); };
      const Eigen::VectorXd zero_e = Eigen::VectorXd::Zero(kComponentCount);
      expect_converges(Jw, [&](double h) { return test::central_difference(of_e, zero_e, h, true); }, 1e-4, what);
      expect_converges(Jg, [&](double h) { return test::central_difference(of_e, zero_e, h, false); }, 1e-4, what);
      const auto of_theta = [&](const Eigen::VectorXd& v) { return chain->ideal_wMg(AxisValues{Vector5d(v)}); };
      expect_converges(J_twistw_theta(*chain, theta),
                       [&](double h) { return test::central_difference(of_theta, theta.v, h, true); }, 1e-4, what);
      expect_converges(J_twistg_theta(*chain, theta),
                       [&](double h) { return test::central_difference(of_theta, theta.v, h, false); }, 1e-4, what);
      // A Jacobian that is zero would pass any tolerance: each column moves the wheel.
      for (int k = 0; k < kAxisCount; ++k) EXPECT_GT(J_twistg_theta(*chain, theta).col(k).norm(), 0.5) << what;
    }
  }
}

// --- The CAFXZY against homogeneous transforms written here ----------------------------------------------------

using Matrix4 = Eigen::Matrix4d;

Matrix4 T4(double x, double y, double z) {
  Matrix4 m = Matrix4::Identity();
  m.col(3).head<3>() << x, y, z;
  return m;
}
Matrix4 R4(const Eigen::Vector3d& axis, double angle) {
  Matrix4 m = Matrix4::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  return m;
}
/// T(δ)·Rx(εx)·Ry(εy)·Rz(εz) (Eq. 9's order).
Matrix4 E4(const ErrorVector& e, int first) {
  return T4(e(first), e(first + 1), e(first + 2)) * R4(Eigen::Vector3d::UnitX(), e(first + 3)) *
         R4(Eigen::Vector3d::UnitY(), e(first + 4)) * R4(Eigen::Vector3d::UnitZ(), e(first + 5));
}

/// The CAFXZY, w → C → A → F → X → Z → Y → g, from the description in docs/machine-model.md: the C table's face
/// 150 mm above the A pivot, A about +x on the bed, X, Z, Y slides on the wheel side, the workpiece side inverted.
Matrix4 cafxzy_by_hand(const ErrorVector& e, const AxisValues& t) {
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY(), ez = Eigen::Vector3d::UnitZ();
  const auto E = [&](ComponentId id) { return e(index(id)); };
  const Matrix4 S_C = T4(E(ComponentId::E_XOC), E(ComponentId::E_YOC), 0.0) * R4(ex, E(ComponentId::E_AOC)) *
                      R4(ey, E(ComponentId::E_BOC));
  const Matrix4 S_A = T4(0.0, E(ComponentId::E_YOA), E(ComponentId::E_ZOA)) * R4(ey, E(ComponentId::E_BOA)) *
                      R4(ez, E(ComponentId::E_COA));
  const Matrix4 AMC = T4(0.0, 0.0, 150.0) * S_C * R4(ez, t[Axis::C] + E(ComponentId::E_COC)) * E4(e, index(ComponentId::delta_xc));
  const Matrix4 FMA = S_A * R4(ex, t[Axis::A] + E(ComponentId::E_AOA)) * E4(e, index(ComponentId::delta_xa)) * S_A.inverse();
  const double x = t[Axis::X], y = t[Axis::Y], z = t[Axis::Z];
  const Matrix4 FMX = T4(x, 0.0, 0.0) * E4(e, index(ComponentId::delta_xx));
  const Matrix4 XMZ = T4(-z * E(ComponentId::S_xz), 0.0, z) * E4(e, index(ComponentId::delta_xz));
  const Matrix4 ZMY = T4(-y * E(ComponentId::S_xy), y, -y * E(ComponentId::S_zy)) * E4(e, index(ComponentId::delta_xy));
  return AMC.inverse() * FMA.inverse() * FMX * XMZ * ZMY;
}

TEST(KinematicChain, CafxzyIsTheHandWrittenChainForAConstantErrorOfEachAxis) {
  const KinematicChain& c = *chain_preset("CAFXZY");
  std::mt19937 rng(47);
  for (int trial = 0; trial < 10; ++trial) {
    const AxisValues theta = c.solve(test::random_pose(rng)).theta;
    // Each axis alone with all its components (motion, squareness, location) at random µm/µrad values.
    for (const Axis axis : kAxes) {
      const ErrorVector all = test::random_errors(rng);
      ErrorVector e = ErrorVector::Zero();
      for (int k = 0; k < kComponentCount; ++k)
        if (c.info(component_at(k)).axis == axis) e(k) = all(k);
      const Matrix4 by_hand = cafxzy_by_hand(e, theta);
      const Matrix4 difference = actual_wMg(c, e, theta).matrix() - by_hand;
      const double position_mm = difference.col(3).head<3>().cwiseAbs().maxCoeff();
      const double rotation = difference.block(0, 0, 3, 3).cwiseAbs().maxCoeff();
      EXPECT_LT(position_mm, 1e-10) << axis_name(axis); // 1e-4 µm
      EXPECT_LT(rotation, 1e-13) << axis_name(axis);
      // And the error moves the wheel by µm (a test that cannot fail would not).
      const Matrix4 moved = by_hand - cafxzy_by_hand(ErrorVector::Zero(), theta);
      EXPECT_GT(moved.col(3).head<3>().norm(), 1e-3) << axis_name(axis);
    }
  }
}

// --- Bad descriptions -------------------------------------------------------------------------------------------

ChainSpec cafxzy_spec_copy() { return chain_preset("CAFXZY")->spec(); }

void expect_refused(ChainSpec s, int axis, const std::string& field, const std::string& words) {
  try {
    make_chain(std::move(s));
    ADD_FAILURE() << "accepted; expected: " << words;
  } catch (const ChainError& e) {
    EXPECT_EQ(e.axis(), axis) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(KinematicChain, BadDescriptionsAreRefusedNamingTheAxisAndField) {
  ChainSpec four = cafxzy_spec_copy();
  four.tool.pop_back();
  expect_refused(four, -1, "", "has 4");
  ChainSpec six = cafxzy_spec_copy();
  six.tool.push_back({"W", AxisKind::Linear, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), Interval{0.0, 1.0}});
  expect_refused(six, -1, "", "has 6");
  ChainSpec twice = cafxzy_spec_copy();
  twice.tool[2].name = "X";
  expect_refused(twice, 4, "name", "named twice");
  ChainSpec zero = cafxzy_spec_copy();
  zero.tool[1].direction = Eigen::Vector3d::Zero();
  expect_refused(zero, 3, "direction", "zero length");
  ChainSpec parallel = cafxzy_spec_copy();
  parallel.tool[2].direction = Eigen::Vector3d::UnitX();
  expect_refused(parallel, 4, "direction", "both move along x");
  ChainSpec no_spindle = cafxzy_spec_copy();
  std::swap(no_spindle.workpiece[0], no_spindle.workpiece[1]);
  expect_refused(no_spindle, 0, "kind", "workpiece spindle");
}

TEST(KinematicChain, SingularAndUnreachablePosesAreNamed) {
  // The CFXZAY's Y rides on the swivel: at a cross angle of 90° Y is parallel to Z and the wheel centre cannot move
  // along x·y's normal.
  AxisPose q{300.0, 10.0, 100.0, std::numbers::pi / 2, 0.3};
  const InverseKinematics ik = cfxzay().solve(q);
  EXPECT_LT(std::abs(ik.linear_det), kSingularDet);
  EXPECT_TRUE(std::isnan(ik.theta[Axis::X]));
  // Outside a stroke: the axis and its stroke named.
  const auto v = cfxzay().outside_stroke(AxisValues{AxisPose{300.0, 250.0, 100.0, 0.2, 0.0}.vector()});
  ASSERT_TRUE(v);
  EXPECT_EQ(v->axis, Axis::Y);
  EXPECT_EQ(v->message, "Y = 250.000 mm is outside its stroke [-200, 200] mm");
}

} // namespace
} // namespace geartopo::machine
