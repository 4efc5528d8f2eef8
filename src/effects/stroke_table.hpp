// geartopo — a law given as a function (a Python function) sampled once per stroke, so that the exact simulation, which
// asks for the law at contacts it finds one by one (a Newton search per flank point), calls the function once per
// stroke and not once per point. The grid: the stroke's Z (its ends ± kMarginZMm) at ≤ kStepZMm and each wheel flank's
// v range (ContactMap::v_lo … v_hi) at ≤ kStepVMm, every node evaluated in one call in a fixed order, then a cubic
// through 4 × 4 nodes (Lagrange, tensor product) at a query: for a law with four bounded derivatives f⁗ the error is
// about h⁴|f⁗|/24 in each direction at most (9h⁴|f⁗|/384 away from the grid's ends; docs/python.md: the figures).
// Units: Z, v mm; values µm.
#pragma once

#include "geartopo/effects/custom_effect.hpp"

#include <array>
#include <vector>

namespace geartopo::effects {

class StrokeTable {
public:
  static constexpr double kStepZMm = 2.0, kStepVMm = 0.5, kMarginZMm = 2.0;

  /// The law at `values` on space `space`'s stroke. Throws NonFiniteDeviation at the first non-finite node (grid
  /// order: side, Z, v), and whatever the law throws.
  StrokeTable(const CustomLaw& law, const std::vector<double>& values, const ContactMap& map,
              const grinding::GrindingSetup& setup, int space);
  /// The law's value (µm) at wheel coordinate v on wheel flank `side`, stroke position Z; both clamped to the grid.
  double deviation_um(int side, double v, double z_stroke_mm) const;
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
  std::array<Axis, 2> v_;
  std::array<std::vector<double>, 2> e_um_; ///< per side, z_.n × v_[side].n, row-major in Z
};

} // namespace geartopo::effects
