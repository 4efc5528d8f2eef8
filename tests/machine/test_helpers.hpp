// geartopo tests — shared helpers for the machine-model tests: random poses and errors, finite differences.
// Units: mm, rad.
#pragma once

#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/machine_model.hpp"

#include <functional>
#include <random>
#include <string>

namespace geartopo::machine::test {

/// Absolute path of a fixture in tests/machine/data.
std::string data_path(const std::string& name);

/// A pose inside the SKMC-1200W strokes (X 50…900, Y ±200, Z 0…800 mm, A ±45°, C any of two turns).
AxisPose random_pose(std::mt19937& rng);

/// Every one of the 43 components random: lengths ±(10…50) µm, angles ±(20…100) µrad, in mm and rad.
ErrorVector random_errors(std::mt19937& rng);

/// Twist of b relative to a: (t; rotation vector) of a⁻¹·b (body, in a's frame) — for finite differences.
Vector6d body_difference(const Pose& a, const Pose& b);
/// Twist of b relative to a in the common base frame: (t; rotation vector) of b·a⁻¹.
Vector6d spatial_difference(const Pose& a, const Pose& b);

/// Central finite-difference Jacobian of a pose-valued function of n parameters at x, as body
/// (spatial = false) or spatial twists, with the same step h for every parameter.
Eigen::MatrixXd central_difference(const std::function<Pose(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
                                   double h, bool spatial);

} // namespace geartopo::machine::test
