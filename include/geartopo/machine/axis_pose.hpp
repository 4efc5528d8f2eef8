// geartopo — axis commands of the five-axis CFXZAY profile grinder (docs/machine-model.md).
//
// q = (X, Y, Z, A, C). Units: X, Y, Z in mm; A and C in rad (files and scenes use deg; convert at the edge).
//   X  radial centre distance, moves the wheel head along the frame's x axis
//   Y  shift of the wheel along its own spindle axis (the wheel frame's y axis)
//   Z  travel along the gear axis (workpiece z, into the gear from the datum face)
//   A  tilt of the wheel head about x, set to the helix angle in use (α in the paper)
//   C  turn of the workpiece table about the gear axis (γ in the paper)
#pragma once

#include <Eigen/Core>

#include <array>
#include <string_view>

namespace geartopo::machine {

/// The five machine axes, in the order of AxisPose and of the columns of every J_*_q (6×5) Jacobian.
enum class Axis : int { X = 0, Y = 1, Z = 2, A = 3, C = 4 };

inline constexpr int kAxisCount = 5;
inline constexpr std::array<Axis, kAxisCount> kAxes = {Axis::X, Axis::Y, Axis::Z, Axis::A, Axis::C};

/// "X", "Y", … for messages.
constexpr std::string_view axis_name(Axis axis) {
  constexpr std::array<std::string_view, kAxisCount> names = {"X", "Y", "Z", "A", "C"};
  return names[static_cast<int>(axis)];
}

/// True for A and C (positions in rad, errors in files against deg).
constexpr bool is_rotary(Axis axis) { return axis == Axis::A || axis == Axis::C; }

using Vector5d = Eigen::Matrix<double, 5, 1>;

/// Axis commands. Linear axes in mm, rotary axes in rad.
struct AxisPose {
  double x = 0.0; ///< X, mm
  double y = 0.0; ///< Y, mm
  double z = 0.0; ///< Z, mm
  double a = 0.0; ///< A (α), rad
  double c = 0.0; ///< C (γ), rad

  /// Position of one axis (mm or rad).
  double operator[](Axis axis) const {
    switch (axis) {
    case Axis::X: return x;
    case Axis::Y: return y;
    case Axis::Z: return z;
    case Axis::A: return a;
    case Axis::C: return c;
    }
    return 0.0;
  }
  double& operator[](Axis axis) {
    switch (axis) {
    case Axis::X: return x;
    case Axis::Y: return y;
    case Axis::Z: return z;
    case Axis::A: return a;
    case Axis::C: break;
    }
    return c;
  }

  /// (X, Y, Z, A, C) as a 5-vector, the order of the Jacobian columns.
  Vector5d vector() const { return (Vector5d() << x, y, z, a, c).finished(); }
  static AxisPose from_vector(const Vector5d& v) { return {v(0), v(1), v(2), v(3), v(4)}; }
};

} // namespace geartopo::machine
