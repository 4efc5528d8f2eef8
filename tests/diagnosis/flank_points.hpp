// Measured points anywhere on the active flanks, for the diagnosis tests (deviation 0 µm; the test sets it).
#pragma once

#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/measurement/measured_points.hpp"

#include <cstdint>
#include <random>
#include <vector>

namespace geartopo::test {

/// `count` points uniform over the active flank (roll length d_Ff … d_a, z 0 … b) of random teeth and flanks.
inline std::vector<measurement::MeasuredPoint> random_flank_points(const gears::GearGeometry& g, int count,
                                                                   std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> tooth(1, g.teeth()), side(0, 1);
  std::uniform_real_distribution<double> xi(g.roll_length_at(g.root_form_diameter_mm()), g.roll_length_at(g.tip_diameter_mm())),
      z(0.0, g.spec().face_width_mm);
  std::vector<measurement::MeasuredPoint> pts(static_cast<size_t>(count));
  for (auto& p : pts) {
    p.tooth = tooth(rng);
    p.flank = side(rng) ? Flank::Right : Flank::Left;
    p.roll_length_mm = xi(rng);
    p.diameter_mm = g.diameter_at_roll_length(p.roll_length_mm);
    p.z_mm = z(rng);
  }
  return pts;
}

} // namespace geartopo::test
