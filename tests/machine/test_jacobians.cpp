// geartopo tests — every Jacobian against central finite differences of the exact chain, with the step-size
// convergence of the differences shown (halving h quarters the error until rounding takes over).
// Units: mm, rad.
#include "test_helpers.hpp"

#include "geartopo/machine/error_table.hpp"
#include "geartopo/machine/first_order.hpp"
#include "geartopo/machine/jacobian.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace geartopo::machine {
namespace {

using test::central_difference;
using test::random_pose;

/// Max error of finite differences with steps h0, h0/2, h0/4, h0/8 against J; checks the O(h²) convergence
/// and that the last error is below final_rel_tol × the largest entry of J (levers reach ~1000 mm/rad).
void expect_converges(const Eigen::MatrixXd& J, const std::function<Eigen::MatrixXd(double)>& fd, double h0,
                      double final_rel_tol) {
  double previous = 0.0;
  for (int k = 0; k < 4; ++k) {
    const double h = h0 / std::pow(2.0, k);
    const double err = (fd(h) - J).cwiseAbs().maxCoeff();
    if (k > 0) {
      EXPECT_GT(err / previous, 0.2) << "h = " << h;
      EXPECT_LT(err / previous, 0.3) << "h = " << h;
    }
    previous = err;
  }
  EXPECT_LT(previous, final_rel_tol * J.cwiseAbs().maxCoeff());
}

Pose ideal_of(const Eigen::VectorXd& v) { return ideal_wMg(AxisPose::from_vector(v)); }

TEST(Jacobians, IdealJTwistgQMatchesFiniteDifferences) {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 20; ++trial) {
    const AxisPose q = random_pose(rng);
    const Eigen::VectorXd x = q.vector();
    expect_converges(J_twistg_q(q), [&](double h) { return central_difference(ideal_of, x, h, false); }, 4e-3, 1e-7);
    expect_converges(J_twistw_q(q), [&](double h) { return central_difference(ideal_of, x, h, true); }, 4e-3, 1e-7);
  }
}

TEST(Jacobians, WheelFrameJacobianClosedForm) {
  // The corrected Eq. 28 (docs/machine-model.md §5), typed independently of the library.
  std::mt19937 rng(32);
  for (int trial = 0; trial < 50; ++trial) {
    const AxisPose q = random_pose(rng);
    const double sa = std::sin(q.a), ca = std::cos(q.a);
    Matrix65 J;
    //     X    Y    Z     A     C
    J << 1.0, 0.0, 0.0, 0.0, q.y * ca,  //
        0.0, 1.0, sa, 0.0, -q.x * ca,   //
        0.0, 0.0, ca, q.y, q.x * sa,    //
        0.0, 0.0, 0.0, 1.0, 0.0,                   //
        0.0, 0.0, 0.0, 0.0, -sa,                   //
        0.0, 0.0, 0.0, 0.0, -ca;
    EXPECT_LT((J_twistg_q(q) - J).cwiseAbs().maxCoeff(), 1e-12 * 2000.0);
    // And the workpiece-frame version is its transport by Ad(wMg).
    EXPECT_LT((J_twistw_q(q) - adjoint(ideal_wMg(q)) * J).cwiseAbs().maxCoeff(), 1e-12 * 2000.0);
  }
}

TEST(Jacobians, ErrorSensitivitiesMatchFiniteDifferencesInEveryComponent) {
  std::mt19937 rng(33);
  MachineData data;
  for (int trial = 0; trial < 10; ++trial) {
    const AxisPose q = random_pose(rng);
    error_jacobians(q, data);
    const Matrix6E Jw = data.J_twistw_e, Jg = data.J_twistg_e;
    const Pose ideal = ideal_wMg(q);
    const auto exact = [&](const Eigen::VectorXd& e) {
      MachineData d;
      return actual_kinematics(ErrorVector(e), q, d);
    };
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(kComponentCount);
    // At e = 0 the exact chain is the ideal one, so the FD twists are the pose-error twists of Eq. 23.
    ASSERT_LT((exact(zero).matrix() - ideal.matrix()).cwiseAbs().maxCoeff(), 1e-9);
    // The chain is linear in the translations, so only angular columns carry O(h²) error: take h large
    // enough for them to dominate rounding (h in rad or mm).
    expect_converges(Jg, [&](double h) { return central_difference(exact, zero, h, false); }, 2e-2, 2e-6);
    expect_converges(Jw, [&](double h) { return central_difference(exact, zero, h, true); }, 2e-2, 2e-6);
  }
}

MachineModel model_with_varying_errors() {
  using test::data_path;
  std::vector<ErrorSource> s = load_error_tables(data_path("x_axis.csv"));
  for (ErrorSource& c : load_error_tables(data_path("c_axis.csv"))) s.push_back(std::move(c));
  s.push_back(load_error_table(data_path("a_axis.csv"), ComponentId::epsilon_xa));
  using enum ComponentId;
  s.push_back(ErrorSource::polynomial(delta_zz, {2.0, 0.01, -1e-5}, "um", "mm"));
  s.push_back(ErrorSource::polynomial(epsilon_yz, {5.0, -0.02, 3e-5}, "urad", "mm"));
  s.push_back(ErrorSource::polynomial(delta_yy, {-3.0, 0.02, 1e-4}, "um", "mm"));
  s.push_back(ErrorSource::polynomial(epsilon_xy, {8.0, 0.1}, "urad", "mm"));
  s.push_back(ErrorSource::polynomial(delta_za, {4.0, 0.5}, "um", "deg"));
  s.push_back(ErrorSource::polynomial(epsilon_za, {30.0, 1.5}, "urad", "deg"));
  s.push_back(ErrorSource::constant(S_xy, 40.0, "urad"));
  s.push_back(ErrorSource::constant(S_zy, -25.0, "urad"));
  s.push_back(ErrorSource::constant(S_xz, 30.0, "urad"));
  s.push_back(ErrorSource::constant(E_XOC, 20.0, "um"));
  s.push_back(ErrorSource::constant(E_BOC, 50.0, "urad"));
  s.push_back(ErrorSource::constant(E_ZOA, -30.0, "um"));
  s.push_back(ErrorSource::constant(E_COA, 60.0, "urad"));
  return MachineModel(Strokes::skmc_1200w(), std::move(s));
}

TEST(Jacobians, ActualChainJacobiansIncludeTheErrorSlopes) {
  const MachineModel model = model_with_varying_errors();
  std::mt19937 rng(34);
  MachineData data;
  const auto actual = [&](const Eigen::VectorXd& v) {
    MachineData d;
    return actual_wMg(model, d, AxisPose::from_vector(v));
  };
  for (int trial = 0; trial < 10; ++trial) {
    AxisPose q = random_pose(rng);
    q.x = std::min(q.x, 890.0);
    actual_jacobians(model, data, q);
    const Eigen::VectorXd x = q.vector();
    expect_converges(data.J_twistg_q, [&](double h) { return central_difference(actual, x, h, false); }, 4e-3, 1e-7);
    expect_converges(data.J_twistw_q, [&](double h) { return central_difference(actual, x, h, true); }, 4e-3, 1e-7);
    // The error slopes matter: the actual Jacobian differs from the ideal one by far more than the FD error.
    EXPECT_GT((data.J_twistg_q - J_twistg_q(q)).cwiseAbs().maxCoeff(), 1e-5);
  }
}

TEST(Jacobians, ActualJacobianOfAnErrorFreeModelIsTheIdealOne) {
  const MachineModel model(Strokes::skmc_1200w());
  MachineData data;
  std::mt19937 rng(35);
  for (int trial = 0; trial < 20; ++trial) {
    const AxisPose q = random_pose(rng);
    actual_jacobians(model, data, q);
    EXPECT_LT((data.J_twistg_q - J_twistg_q(q)).cwiseAbs().maxCoeff(), 1e-12 * 2000.0);
    EXPECT_LT((data.J_twistw_q - J_twistw_q(q)).cwiseAbs().maxCoeff(), 1e-12 * 2000.0);
  }
}

} // namespace
} // namespace geartopo::machine
