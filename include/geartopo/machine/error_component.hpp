// geartopo — the 43 geometric error components of the CFXZAY grinder (docs/error-components.md).
//
// The paper's Table 1 (33): for each axis k ∈ {X, Y, Z, A, C} the linear errors δ_xk, δ_yk, δ_zk and the
// angular errors ε_xk, ε_yk, ε_zk, functions of axis k's own position; the squarenesses S_xy, S_zy, S_xz.
// Plus the ISO 230-7 location errors of the two rotary axis lines (10), position independent:
//   C (axis line along z): E_XOC, E_YOC offsets, E_AOC, E_BOC tilts, E_COC zero-position error;
//   A (axis line along x): E_YOA, E_ZOA offsets, E_BOA, E_COA tilts, E_AOA zero-position error.
// Units: inside the library lengths are mm and angles rad; in files δ and offsets are µm, ε, S and tilts µrad.
#pragma once

#include "geartopo/machine/axis_pose.hpp"

#include <Eigen/Core>

#include <array>
#include <optional>
#include <string_view>

namespace geartopo::machine {

// clang-format off
/// Index of a component in every error vector (ErrorVector) and in the columns of J_twist*_e (6×43).
enum class ComponentId : int {
  delta_xx, delta_yx, delta_zx, epsilon_xx, epsilon_yx, epsilon_zx,   // X axis, functions of x
  delta_xy, delta_yy, delta_zy, epsilon_xy, epsilon_yy, epsilon_zy,   // Y axis, functions of y
  delta_xz, delta_yz, delta_zz, epsilon_xz, epsilon_yz, epsilon_zz,   // Z axis, functions of z
  delta_xa, delta_ya, delta_za, epsilon_xa, epsilon_ya, epsilon_za,   // A axis, functions of α
  delta_xc, delta_yc, delta_zc, epsilon_xc, epsilon_yc, epsilon_zc,   // C axis, functions of γ (periodic)
  S_xy, S_zy, S_xz,                                                   // squareness, constants
  E_XOC, E_YOC, E_AOC, E_BOC, E_COC,                                  // C axis line location, constants
  E_YOA, E_ZOA, E_BOA, E_COA, E_AOA,                                  // A axis line location, constants
};
// clang-format on

inline constexpr int kComponentCount = 43;
/// Number of position-dependent components (the first 30, five axes × six).
inline constexpr int kMotionComponentCount = 30;

/// All component values at one axis pose, indexed by ComponentId. mm and rad.  // 43×1
using ErrorVector = Eigen::Matrix<double, kComponentCount, 1>;

/// What a component measures, which decides its unit.
enum class Quantity { Length, Angle };

struct ComponentInfo {
  ComponentId id;
  std::string_view name;       ///< code name, also the CSV column stem: "delta_xx", "epsilon_zc", "S_xy", "E_XOC"
  std::string_view symbol;     ///< printed symbol: "δ_xx", "ε_zc", "S_xy", "E_XOC"
  Axis axis;                   ///< the axis it belongs to (its position argument if position dependent)
  Quantity quantity;           ///< Length (mm inside, µm in files) or Angle (rad inside, µrad in files)
  bool position_dependent;     ///< false: a constant (squareness, axis-line location)
  std::string_view meaning;    ///< one line, for messages and docs
};

constexpr int index(ComponentId id) { return static_cast<int>(id); }
constexpr ComponentId component_at(int i) { return static_cast<ComponentId>(i); }

/// Description of one component. Never fails for a valid id.
const ComponentInfo& info(ComponentId id);
/// Component by code name (exact, case-sensitive: "delta_xx", "S_xy", "E_XOC"); nullopt if unknown.
std::optional<ComponentId> component_from_name(std::string_view name);

/// The six motion components of one axis, in the order δ_x, δ_y, δ_z, ε_x, ε_y, ε_z.
constexpr ComponentId motion_component(Axis axis, int k /* 0..5 */) {
  return component_at(6 * static_cast<int>(axis) + k);
}

// --- Units -------------------------------------------------------------------------------------------------

/// Factor that converts a value in `unit` of quantity q to the internal unit (mm or rad); nullopt if the
/// unit is not one of that quantity's units. Lengths: nm, um (µm), mm. Angles: urad (µrad), mrad, rad, arcsec.
std::optional<double> value_unit_scale(Quantity q, std::string_view unit);
/// The same for an axis position: linear axes mm (um accepted); rotary axes deg or rad.
std::optional<double> position_unit_scale(Axis axis, std::string_view unit);
/// True if `unit` is known for any quantity or position (to tell "unknown unit" from "wrong kind of unit").
bool is_known_unit(std::string_view unit);
/// The unit files use by default for a quantity: "um" or "urad".
constexpr std::string_view file_unit(Quantity q) { return q == Quantity::Length ? "um" : "urad"; }

} // namespace geartopo::machine
