// geartopo tests — each component alone moves the wheel as docs/error-components.md says.
// The expectations are exact (no small-angle step) unless stated. Units: mm, rad; inputs in µm / µrad.
#include "test_helpers.hpp"

#include "geartopo/machine/transforms.hpp"
#include "geartopo/core/units.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace geartopo::machine {
namespace {

using enum ComponentId;

/// The actual wheel pose with exactly one component at `value` (file units: µm or µrad).
Pose with_one(ComponentId id, double value, const AxisPose& q) {
  const ComponentInfo& c = info(id);
  const MachineModel model(Strokes::skmc_1200w(), {ErrorSource::constant(id, value, file_unit(c.quantity))});
  MachineData data;
  return actual_wMg(model, data, q);
}

/// Displacement of the wheel centre (origin of g) in the workpiece frame w, mm.
Eigen::Vector3d shift(ComponentId id, double value, const AxisPose& q) {
  return with_one(id, value, q).translation() - ideal_wMg(q).translation();
}

void expect_vec(const Eigen::Vector3d& got, const Eigen::Vector3d& want, double tol = 1e-12) {
  EXPECT_LT((got - want).norm(), tol) << "got " << got.transpose() << "\nwant " << want.transpose();
}

const AxisPose kAt0{400.0, 60.0, 300.0, 25.0 * units::kRadPerDeg, 0.0};       // γ = 0: w and F coincide
const AxisPose kAt90{400.0, 60.0, 300.0, 25.0 * units::kRadPerDeg, 90.0 * units::kRadPerDeg};

TEST(Components, DeltaXxMovesTheWheelAlongFrameX) {
  expect_vec(shift(delta_xx, 10.0, kAt0), {0.010, 0.0, 0.0});  // +x of w at γ = 0
  expect_vec(shift(delta_xx, 10.0, kAt90), {0.0, -0.010, 0.0}); // frame x is w's −y at γ = 90°
}

TEST(Components, DeltaZzMovesTheWheelAlongTheGearAxis) {
  expect_vec(shift(delta_zz, 5.0, kAt90), {0.0, 0.0, 0.005});
}

TEST(Components, DeltaYyMovesTheWheelAlongItsSpindle) {
  const Eigen::Vector3d spindle = ideal_wMg(kAt90).linear().col(1);
  expect_vec(shift(delta_yy, 5.0, kAt90), 0.005 * spindle);
}

TEST(Components, CAxisLineOffsetShiftRotatesWithGamma) {
  // The gear axis is the actual C axis line, 10 µm along +x of F: seen from the gear the wheel moves by
  // −Rz(−γ)·(10 µm, 0, 0) — a fixed 10 µm that turns with −γ in w.
  for (double g_deg : {0.0, 90.0, 210.0, 333.0}) {
    AxisPose q = kAt0;
    q.c = g_deg * units::kRadPerDeg;
    const Eigen::Vector3d want = -(rot_z(-q.c) * Eigen::Vector3d(0.010, 0.0, 0.0));
    expect_vec(shift(E_XOC, 10.0, q), want);
    EXPECT_NEAR(shift(E_XOC, 10.0, q).norm(), 0.010, 1e-12);
  }
  expect_vec(shift(E_XOC, 10.0, kAt0), {-0.010, 0.0, 0.0}); // the centre distance shrinks by 10 µm
  expect_vec(shift(E_YOC, 10.0, kAt0), {0.0, -0.010, 0.0});
}

TEST(Components, CRadialErrorMotionIsInTheTableFrame) {
  // δ_xc is a displacement of the table along its own x (Eq. 18: FMC = Rz(γ)·E_C): in w it does not turn.
  expect_vec(shift(delta_xc, 10.0, kAt0), {-0.010, 0.0, 0.0});
  expect_vec(shift(delta_xc, 10.0, kAt90), {-0.010, 0.0, 0.0});
}

TEST(Components, EpsilonZcTurnsTheWheelByMinusEpsilonAboutTheGearAxis) {
  const double eps = 100e-6;
  const Pose actual = with_one(epsilon_zc, 100.0, kAt90);
  const Pose ideal = ideal_wMg(kAt90);
  // Exactly: the table over-turns by ε, so relative to the gear the wheel turns by −ε about w's z.
  EXPECT_LT((actual.matrix() - (Rz(-eps) * ideal).matrix()).cwiseAbs().maxCoeff(), 1e-12);
  // Same as commanding γ + ε.
  AxisPose q = kAt90;
  q.c += eps;
  EXPECT_LT((actual.matrix() - ideal_wMg(q).matrix()).cwiseAbs().maxCoeff(), 1e-12);
  // The w twist is a pure rotation (translation of E_w is zero) although the wheel centre moves by ≈ −ε ẑ × p.
  MachineData data;
  ErrorVector e = ErrorVector::Zero();
  e(index(epsilon_zc)) = eps;
  const PoseErrorTwists t = exact_pose_error(e, kAt90, data);
  expect_vec(t.w.head<3>(), Eigen::Vector3d::Zero());
  expect_vec(t.w.tail<3>(), {0.0, 0.0, -eps}, 1e-18);
  // (first order: the neglected term is ε²·|p|/2 ≈ 2 nm here)
  expect_vec(shift(epsilon_zc, 100.0, kAt90), -eps * Eigen::Vector3d::UnitZ().cross(ideal.translation()), 5e-6);
  // E_COC is the same motion.
  EXPECT_LT((with_one(E_COC, 100.0, kAt90).matrix() - actual.matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Components, SquarenessSxyLeansTheYTravelTowardsMinusX) {
  AxisPose q = kAt0;
  q.y = 100.0;
  expect_vec(shift(S_xy, 50.0, q), {-0.005, 0.0, 0.0}); // −y·S_xy along x
  q.c = 90.0 * units::kRadPerDeg;
  expect_vec(shift(S_xy, 50.0, q), {0.0, 0.005, 0.0});
  q.y = 0.0;
  expect_vec(shift(S_xy, 50.0, q), Eigen::Vector3d::Zero());
}

TEST(Components, SquarenessSzyAndSxz) {
  AxisPose q = kAt0;
  q.y = 100.0;
  // −y·S_zy along the A body's z, which is (0, −sin α, cos α) in F.
  expect_vec(shift(S_zy, 50.0, q), -0.005 * Eigen::Vector3d(0.0, -std::sin(q.a), std::cos(q.a)));
  q.z = 500.0;
  expect_vec(shift(S_xz, 30.0, q), {-0.015, 0.0, 0.0}); // −z·S_xz along x (Eq. 16 corrected: z, not x)
}

TEST(Components, CAxisLineTiltTiltsTheGearAxis) {
  const double a = 100e-6;
  // FMC = Rx(E_AOC)·Rz(γ): at γ = 0 the wheel pose seen from the gear is Rx(−E_AOC)·wMg.
  const Pose actual = with_one(E_AOC, 100.0, kAt0);
  EXPECT_LT((actual.matrix() - (Rx(-a) * ideal_wMg(kAt0)).matrix()).cwiseAbs().maxCoeff(), 1e-12);
  // At height z the wheel moves by ≈ (0, +a·z, −a·y_w) (first order: neglected a²·|p|/2 ≈ 2 nm).
  const Eigen::Vector3d p = ideal_wMg(kAt0).translation();
  expect_vec(shift(E_AOC, 100.0, kAt0), {0.0, a * p.z(), -a * p.y()}, 5e-6);
}

TEST(Components, AAxisLineLocationActsOnlyWhenATurns) {
  AxisPose q0 = kAt0;
  q0.a = 0.0;
  expect_vec(shift(E_ZOA, 30.0, q0), Eigen::Vector3d::Zero());
  expect_vec(shift(E_COA, 60.0, q0), Eigen::Vector3d::Zero());
  // Offset o along z of the A axis line: the wheel moves by (I − Rx(α))·(0, 0, o).
  const double o = 0.030, a = kAt0.a;
  expect_vec(shift(E_ZOA, 30.0, kAt0), {0.0, std::sin(a) * o, (1.0 - std::cos(a)) * o});
  // Tilt about z: A turns about (cos c, sin c, 0) instead of x.
  const double c = 60e-6;
  const Pose actual = with_one(E_COA, 60.0, kAt0);
  const Pose ZMA = Pose(Eigen::AngleAxisd(a, Eigen::Vector3d(std::cos(c), std::sin(c), 0.0)));
  const Pose want = translation(kAt0.x, 0.0, kAt0.z) * ZMA * translation(0.0, kAt0.y, 0.0);
  EXPECT_LT((actual.matrix() - want.matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Components, EpsilonXaAndEAOAAreAnAngleError) {
  AxisPose q = kAt90;
  const Pose actual = with_one(epsilon_xa, 100.0, q);
  q.a += 100e-6;
  EXPECT_LT((actual.matrix() - ideal_wMg(q).matrix()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((with_one(E_AOA, 100.0, kAt90).matrix() - actual.matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Components, YawOfXSwingsTheWheelHeadAboutTheCarriage) {
  // FMX = Tx(x)·Rz(ε_zx): the head turns about z through the X carriage; the wheel at (0, y cosα, ·) in X
  // swings to x = −sin ε · y cosα.
  const double eps = 50e-6;
  const double r = kAt0.y * std::cos(kAt0.a);
  expect_vec(shift(epsilon_zx, 50.0, kAt0), {-std::sin(eps) * r, (std::cos(eps) - 1.0) * r, 0.0});
}

} // namespace
} // namespace geartopo::machine
