// The error rotation R(ε) = Rx(εx)·Ry(εy)·Rz(εz) as the chain computes it (written-out product, Taylor sin and cos
// below 10⁻³ rad) against its definition: the product of the three elementary rotations with the library's sin and
// cos. Truth: std::sin, std::cos and the matrix product. Bounds: 1e-15 relative for sin and cos (≈ 5 ulp), 1e-15
// per element of R (entries of size ≤ 1).
#include "geartopo/machine/transforms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace geartopo::machine {
namespace {

TEST(Transforms, SinCosBelowTheSmallAngleBoundAreTheLibrarysToRounding) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-kSmallAngleRad, kSmallAngleRad);
  std::vector<double> angles = {0.0, -0.0, 1e-300, 1e-12, -3e-7, 5e-6, 0.999999e-3, -0.999999e-3};
  for (int k = 0; k < 20000; ++k) angles.push_back(u(rng) * std::pow(10.0, -3.0 * (k % 3))); // µrad to mrad
  for (const double t : angles) {
    double s, c;
    sin_cos(t, s, c);
    EXPECT_LE(std::abs(s - std::sin(t)), 1e-15 * std::abs(std::sin(t))) << t;
    EXPECT_LE(std::abs(c - std::cos(t)), 1e-15) << t;
  }
}

TEST(Transforms, SinCosAboveTheBoundIsTheLibrarys) {
  for (const double t : {1e-3, -1e-3, 0.01, 0.7, -2.5, 6.2}) {
    double s, c;
    sin_cos(t, s, c);
    EXPECT_EQ(s, std::sin(t));
    EXPECT_EQ(c, std::cos(t));
  }
}

TEST(Transforms, ErrorRotationIsTheProductOfTheThreeElementaryRotations) {
  std::mt19937 rng(29);
  for (const double size : {1e-6, 1e-4, 9e-4, 0.3, 2.0}) { // µrad errors, and angles beyond the Taylor range
    std::uniform_real_distribution<double> u(-size, size);
    for (int k = 0; k < 2000; ++k) {
      const Eigen::Vector3d eps(u(rng), u(rng), u(rng));
      const Eigen::Matrix3d expected = rot_x(eps.x()) * rot_y(eps.y()) * rot_z(eps.z());
      ASSERT_LE((error_rotation(eps) - expected).cwiseAbs().maxCoeff(), 1e-15) << eps.transpose();
    }
  }
}

} // namespace
} // namespace geartopo::machine
