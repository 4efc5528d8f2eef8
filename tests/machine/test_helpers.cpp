// geartopo tests — helpers (see test_helpers.hpp). Units: mm, rad.
#include "test_helpers.hpp"

#include <numbers>

namespace geartopo::machine::test {

std::string data_path(const std::string& name) { return std::string(GEARTOPO_MACHINE_TEST_DATA) + "/" + name; }

AxisPose random_pose(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr double deg = std::numbers::pi / 180.0;
  return {50.0 + 850.0 * u(rng), -200.0 + 400.0 * u(rng), 800.0 * u(rng), (-45.0 + 90.0 * u(rng)) * deg,
          (-360.0 + 1080.0 * u(rng)) * deg};
}

ErrorVector random_errors(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  ErrorVector e;
  for (int i = 0; i < kComponentCount; ++i) {
    const double sign = u(rng) < 0.5 ? -1.0 : 1.0;
    const double mag = info(component_at(i)).quantity == Quantity::Length ? (10.0 + 40.0 * u(rng)) * 1e-3
                                                                         : (20.0 + 80.0 * u(rng)) * 1e-6;
    e(i) = sign * mag;
  }
  return e;
}

Vector6d body_difference(const Pose& a, const Pose& b) { return pose_error_twist(a.inverse(Eigen::Isometry) * b); }
Vector6d spatial_difference(const Pose& a, const Pose& b) { return pose_error_twist(b * a.inverse(Eigen::Isometry)); }

Eigen::MatrixXd central_difference(const std::function<Pose(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
                                   double h, bool spatial) {
  const Pose f0 = f(x);
  Eigen::MatrixXd J(6, x.size());
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    Eigen::VectorXd xp = x, xm = x;
    xp(j) += h;
    xm(j) -= h;
    const Vector6d dp = spatial ? spatial_difference(f0, f(xp)) : body_difference(f0, f(xp));
    const Vector6d dm = spatial ? spatial_difference(f0, f(xm)) : body_difference(f0, f(xm));
    J.col(j) = (dp - dm) / (2.0 * h);
  }
  return J;
}

} // namespace geartopo::machine::test
