// geartopo — units. Internally every length is mm, every angle rad, every time s; files and messages use µm for
// deviations and small errors, µrad for small machine angles, deg for axis positions and gear angles (docs/
// conventions.md). Conversions are named by direction, "to_from": um_from_mm(x) takes mm and gives µm, so a reader
// sees the units on both sides of every conversion and no bare 1e3 or π/180 stands in the code.
#pragma once

#include <numbers>

namespace geartopo::units {

inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;
inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;
inline constexpr double kUmPerMm = 1e3;
inline constexpr double kMmPerUm = 1e-3;
inline constexpr double kUradPerRad = 1e6;
inline constexpr double kRadPerUrad = 1e-6;
inline constexpr double kSPerMin = 60.0;

constexpr double rad_from_deg(double deg) { return deg * kRadPerDeg; }
constexpr double deg_from_rad(double rad) { return rad * kDegPerRad; }
constexpr double um_from_mm(double mm) { return mm * kUmPerMm; }
constexpr double mm_from_um(double um) { return um * kMmPerUm; }
constexpr double urad_from_rad(double rad) { return rad * kUradPerRad; }
constexpr double rad_from_urad(double urad) { return urad * kRadPerUrad; }
constexpr double s_from_ms(double ms) { return ms * 1e-3; }
/// A feed in mm/min as mm/s.
constexpr double mm_per_s_from_mm_per_min(double mm_per_min) { return mm_per_min / kSPerMin; }

} // namespace geartopo::units
