// geartopo — table of the 43 error components and the units files may use. Units: mm, rad inside.
#include "geartopo/machine/error_component.hpp"

#include <numbers>

namespace geartopo::machine {

namespace {

using enum ComponentId;
constexpr Quantity L = Quantity::Length;
constexpr Quantity G = Quantity::Angle;

// Order must follow ComponentId (checked by a static_assert below and by the tests).
constexpr std::array<ComponentInfo, kComponentCount> kInfo = {{
    {delta_xx, "delta_xx", "δ_xx", Axis::X, L, true, "positioning error of X (along x)"},
    {delta_yx, "delta_yx", "δ_yx", Axis::X, L, true, "straightness of X in y"},
    {delta_zx, "delta_zx", "δ_zx", Axis::X, L, true, "straightness of X in z"},
    {epsilon_xx, "epsilon_xx", "ε_xx", Axis::X, G, true, "roll of X (about x)"},
    {epsilon_yx, "epsilon_yx", "ε_yx", Axis::X, G, true, "pitch of X (about y)"},
    {epsilon_zx, "epsilon_zx", "ε_zx", Axis::X, G, true, "yaw of X (about z)"},
    {delta_xy, "delta_xy", "δ_xy", Axis::Y, L, true, "straightness of Y in x"},
    {delta_yy, "delta_yy", "δ_yy", Axis::Y, L, true, "positioning error of Y (along the spindle)"},
    {delta_zy, "delta_zy", "δ_zy", Axis::Y, L, true, "straightness of Y in z"},
    {epsilon_xy, "epsilon_xy", "ε_xy", Axis::Y, G, true, "angular error of Y about x"},
    {epsilon_yy, "epsilon_yy", "ε_yy", Axis::Y, G, true, "roll of Y (about y)"},
    {epsilon_zy, "epsilon_zy", "ε_zy", Axis::Y, G, true, "angular error of Y about z"},
    {delta_xz, "delta_xz", "δ_xz", Axis::Z, L, true, "straightness of Z in x"},
    {delta_yz, "delta_yz", "δ_yz", Axis::Z, L, true, "straightness of Z in y"},
    {delta_zz, "delta_zz", "δ_zz", Axis::Z, L, true, "positioning error of Z (along z)"},
    {epsilon_xz, "epsilon_xz", "ε_xz", Axis::Z, G, true, "angular error of Z about x"},
    {epsilon_yz, "epsilon_yz", "ε_yz", Axis::Z, G, true, "angular error of Z about y"},
    {epsilon_zz, "epsilon_zz", "ε_zz", Axis::Z, G, true, "roll of Z (about z)"},
    {delta_xa, "delta_xa", "δ_xa", Axis::A, L, true, "axial error motion of A (along x)"},
    {delta_ya, "delta_ya", "δ_ya", Axis::A, L, true, "radial error motion of A along the A body's y"},
    {delta_za, "delta_za", "δ_za", Axis::A, L, true, "radial error motion of A along the A body's z"},
    {epsilon_xa, "epsilon_xa", "ε_xa", Axis::A, G, true, "angular positioning error of A (about x)"},
    {epsilon_ya, "epsilon_ya", "ε_ya", Axis::A, G, true, "tilt error motion of A about the A body's y"},
    {epsilon_za, "epsilon_za", "ε_za", Axis::A, G, true, "tilt error motion of A about the A body's z"},
    {delta_xc, "delta_xc", "δ_xc", Axis::C, L, true, "radial error motion of C along the table's x"},
    {delta_yc, "delta_yc", "δ_yc", Axis::C, L, true, "radial error motion of C along the table's y"},
    {delta_zc, "delta_zc", "δ_zc", Axis::C, L, true, "axial error motion of C (along z)"},
    {epsilon_xc, "epsilon_xc", "ε_xc", Axis::C, G, true, "tilt error motion of C about the table's x"},
    {epsilon_yc, "epsilon_yc", "ε_yc", Axis::C, G, true, "tilt error motion of C about the table's y"},
    {epsilon_zc, "epsilon_zc", "ε_zc", Axis::C, G, true, "angular positioning error of C (about z)"},
    {S_xy, "S_xy", "S_xy", Axis::Y, G, false, "squareness of Y to X (Y travel leans towards −x)"},
    {S_zy, "S_zy", "S_zy", Axis::Y, G, false, "squareness of Y to Z (Y travel leans towards −z)"},
    {S_xz, "S_xz", "S_xz", Axis::Z, G, false, "squareness of Z to X (Z travel leans towards −x)"},
    {E_XOC, "E_XOC", "E_XOC", Axis::C, L, false, "x offset of the C axis line"},
    {E_YOC, "E_YOC", "E_YOC", Axis::C, L, false, "y offset of the C axis line"},
    {E_AOC, "E_AOC", "E_AOC", Axis::C, G, false, "tilt of the C axis line about x"},
    {E_BOC, "E_BOC", "E_BOC", Axis::C, G, false, "tilt of the C axis line about y"},
    {E_COC, "E_COC", "E_COC", Axis::C, G, false, "zero-position error of C"},
    {E_YOA, "E_YOA", "E_YOA", Axis::A, L, false, "y offset of the A axis line"},
    {E_ZOA, "E_ZOA", "E_ZOA", Axis::A, L, false, "z offset of the A axis line"},
    {E_BOA, "E_BOA", "E_BOA", Axis::A, G, false, "tilt of the A axis line about y"},
    {E_COA, "E_COA", "E_COA", Axis::A, G, false, "tilt of the A axis line about z"},
    {E_AOA, "E_AOA", "E_AOA", Axis::A, G, false, "zero-position error of A"},
}};

constexpr bool info_in_order() {
  for (int i = 0; i < kComponentCount; ++i)
    if (index(kInfo[static_cast<std::size_t>(i)].id) != i) return false;
  return true;
}
static_assert(info_in_order(), "kInfo must list the components in ComponentId order");
static_assert(index(E_AOA) + 1 == kComponentCount);

constexpr double kPi = std::numbers::pi;

} // namespace

const ComponentInfo& info(ComponentId id) { return kInfo[static_cast<std::size_t>(index(id))]; }

std::optional<ComponentId> component_from_name(std::string_view name) {
  for (const auto& c : kInfo)
    if (c.name == name) return c.id;
  return std::nullopt;
}

std::optional<double> value_unit_scale(Quantity q, std::string_view unit) {
  if (q == Quantity::Length) {
    if (unit == "nm") return 1e-6;
    if (unit == "um" || unit == "µm") return 1e-3;
    if (unit == "mm") return 1.0;
  } else {
    if (unit == "urad" || unit == "µrad") return 1e-6;
    if (unit == "mrad") return 1e-3;
    if (unit == "rad") return 1.0;
    if (unit == "arcsec") return kPi / 648000.0;
  }
  return std::nullopt;
}

std::optional<double> position_unit_scale(Axis axis, std::string_view unit) {
  if (is_rotary(axis)) {
    if (unit == "deg") return kPi / 180.0;
    if (unit == "rad") return 1.0;
  } else {
    if (unit == "mm") return 1.0;
    if (unit == "um" || unit == "µm") return 1e-3;
  }
  return std::nullopt;
}

bool is_known_unit(std::string_view unit) {
  return value_unit_scale(Quantity::Length, unit) || value_unit_scale(Quantity::Angle, unit) ||
         position_unit_scale(Axis::X, unit) || position_unit_scale(Axis::C, unit);
}

} // namespace geartopo::machine
