// geartopo evaluation — pitch and runout. Units: µm (deviations, arcs, runout), rad (angles).
#include "geartopo/evaluation/pitch.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace geartopo::evaluation {

namespace {

void check_geometry(const PitchGeometry& g) {
  const double half_pi = 0.5 * std::numbers::pi;
  if (!std::isfinite(g.base_helix_angle_rad) || !(std::abs(g.base_helix_angle_rad) < half_pi))
    throw std::invalid_argument(
        fmt::format("pitch geometry refused: base helix angle {} rad is outside (−π/2, π/2)", g.base_helix_angle_rad));
  if (!std::isfinite(g.transverse_pressure_angle_rad) || !(g.transverse_pressure_angle_rad > 0.0) ||
      !(g.transverse_pressure_angle_rad < half_pi))
    throw std::invalid_argument(fmt::format(
        "pitch geometry refused: transverse pressure angle {} rad is outside (0, π/2)", g.transverse_pressure_angle_rad));
  if (!std::isfinite(g.space_half_angle_rad) || !(g.space_half_angle_rad >= 0.0) ||
      !(g.space_half_angle_rad < half_pi))
    throw std::invalid_argument(fmt::format(
        "pitch geometry refused: space half angle {} rad is outside [0, π/2)", g.space_half_angle_rad));
}

void check_values(std::span<const double> v, const char* what) {
  if (v.size() < 3)
    throw std::invalid_argument(fmt::format("{}: {} teeth; pitch and runout need at least 3", what, v.size()));
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw std::invalid_argument(fmt::format("{}: deviation of tooth {} is not finite", what, i + 1));
}

} // namespace

double flank_position_um(double normal_deviation_um, Flank side, const PitchGeometry& g) {
  return side_sign(side) * normal_deviation_um /
         (std::cos(g.base_helix_angle_rad) * std::cos(g.transverse_pressure_angle_rad));
}

int default_sector_pitches(int teeth) {
  if (teeth < 3) throw std::invalid_argument(fmt::format("sector pitch: {} teeth; at least 3 are needed", teeth));
  const int k = (teeth + 4) / 8; // z/8 rounded half up (integer arithmetic: exact)
  return std::clamp(k, 2, teeth - 1);
}

PitchEvaluation evaluate_pitch(std::span<const double> normal_deviation_um, Flank side, const PitchGeometry& g,
                               int sector_pitches) {
  check_geometry(g);
  check_values(normal_deviation_um, "pitch");
  const std::size_t z = normal_deviation_um.size();
  const int zi = static_cast<int>(z);
  const int k = sector_pitches == 0 ? default_sector_pitches(zi) : sector_pitches;
  if (k < 1 || k > zi - 1)
    throw std::invalid_argument(fmt::format("sector pitch: k = {} is outside 1..{}", k, zi - 1));

  PitchEvaluation r;
  r.side = side;
  r.sector_pitches = k;
  r.position_um.resize(z);
  for (std::size_t j = 0; j < z; ++j) r.position_um[j] = flank_position_um(normal_deviation_um[j], side, g);
  const auto& e = r.position_um;

  r.single_pitch_um.resize(z);
  r.index_um.resize(z);
  for (std::size_t j = 0; j < z; ++j) {
    r.single_pitch_um[j] = e[(j + 1) % z] - e[j];
    r.index_um[j] = e[j] - e[0];
    r.f_p_um = std::max(r.f_p_um, std::abs(r.single_pitch_um[j]));
    r.F_pk_um = std::max(r.F_pk_um, std::abs(e[(j + static_cast<std::size_t>(k)) % z] - e[j]));
  }
  const auto [mn, mx] = std::minmax_element(e.begin(), e.end());
  r.F_p_um = *mx - *mn;
  return r;
}

RunoutEvaluation evaluate_runout(std::span<const double> right_normal_um, std::span<const double> left_normal_um,
                                 const PitchGeometry& g) {
  check_geometry(g);
  check_values(right_normal_um, "runout (right flanks)");
  check_values(left_normal_um, "runout (left flanks)");
  if (right_normal_um.size() != left_normal_um.size())
    throw std::invalid_argument(fmt::format("runout: {} right flanks but {} left flanks", right_normal_um.size(),
                                            left_normal_um.size()));
  const std::size_t z = right_normal_um.size();
  const double denom = 2.0 * std::cos(g.base_helix_angle_rad) *
                       std::sin(g.transverse_pressure_angle_rad + g.space_half_angle_rad);
  RunoutEvaluation r;
  r.radial_um.resize(z);
  for (std::size_t s = 0; s < z; ++s) r.radial_um[s] = (right_normal_um[s] + left_normal_um[(s + 1) % z]) / denom;
  const auto [mn, mx] = std::minmax_element(r.radial_um.begin(), r.radial_um.end());
  r.F_r_um = *mx - *mn;
  return r;
}

} // namespace geartopo::evaluation
