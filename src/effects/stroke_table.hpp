// geartopo — a law given as a function (a Python function) sampled once per stroke, so that the exact simulation, which
// asks for the law at contacts it finds one by one (a Newton search per flank point), calls the function once per
// stroke and not once per point. The grid: the stroke's Z (from end to end: the time |Z − Z_begin|/feed has a kink at
// the stroke's start, which a node beyond it would smear) at ≤ kStepZMm and, on each wheel
// flank, the roll length ξ of the flank point it grinds (ContactMap, over v_lo … v_hi) at ≤ kStepRollMm — in ξ, not
// in the wheel's v, because ξ(v) is steep near the root of a small gear while the flank's x, y, r, n are smooth in ξ.
// Every node is evaluated in one call in a fixed order, then a cubic through 4 × 4 nodes (Lagrange, tensor product)
// at a query: for a law with four bounded derivatives f⁗ the error is about h⁴|f⁗|/24 in each direction at most
// (9h⁴|f⁗|/384 away from the grid's ends; docs/python.md: the figures).
// Units: Z, ξ mm; values µm.
#pragma once

#include "geartopo/effects/custom_effect.hpp"

#include <array>
#include <vector>

namespace geartopo::effects {

class StrokeTable {
public:
  static constexpr double kStepZMm = 8.0, kStepRollMm = 2.0;

  /// The law at `values` on space `space`'s stroke. Throws NonFiniteDeviation at the first non-finite node (grid
  /// order: side, Z, v), and whatever the law throws.
  StrokeTable(const CustomLaw& law, const std::vector<double>& values, const ContactMap& map,
              const grinding::GrindingSetup& setup, int space);
  /// The law's value (µm) at roll length ξ on wheel flank `side` (ContactMap::roll_at), stroke position Z; both
  /// clamped to the grid.
  double deviation_um(int side, double xi, double z_stroke_mm) const;
  /// The number of nodes (both sides): the points one call evaluates.
  std::size_t nodes() const;

private:
  struct Axis {
    double start = 0.0, step = 1.0;
    int n = 4;
    /// The first of the 4 nodes around x and the 4 Lagrange weights at x (clamped into the axis).
    int weights(double x, std::array<double, 4>& w) const;
  };
  static Axis axis(double lo, double hi, double step);

  Axis z_;
  std::array<Axis, 2> xi_;
  std::array<std::vector<double>, 2> e_um_; ///< per side, z_.n × xi_[side].n, row-major in Z
};

} // namespace geartopo::effects
