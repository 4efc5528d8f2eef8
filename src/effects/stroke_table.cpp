#include "stroke_table.hpp"

#include <algorithm>
#include <cmath>

namespace geartopo::effects {

StrokeTable::Axis StrokeTable::axis(double lo, double hi, double step) {
  Axis a;
  a.n = std::max(4, static_cast<int>(std::ceil((hi - lo) / step)) + 1);
  a.start = lo;
  a.step = (hi - lo) / (a.n - 1);
  return a;
}

int StrokeTable::Axis::weights(double x, std::array<double, 4>& w) const {
  const double u = std::clamp((x - start) / step, 0.0, static_cast<double>(n - 1));
  const int i0 = std::clamp(static_cast<int>(std::floor(u)) - 1, 0, n - 4);
  const double s = u - i0; // in node units from node i0: the nodes are at 0, 1, 2, 3
  w[0] = -(s - 1.0) * (s - 2.0) * (s - 3.0) / 6.0;
  w[1] = s * (s - 2.0) * (s - 3.0) / 2.0;
  w[2] = -s * (s - 1.0) * (s - 3.0) / 2.0;
  w[3] = s * (s - 1.0) * (s - 2.0) / 6.0;
  return i0;
}

StrokeTable::StrokeTable(const CustomLaw& law, const std::vector<double>& values, const ContactMap& map,
                         const grinding::GrindingSetup& setup, int space) {
  const auto& path = setup.path();
  const auto& stroke = path.strokes()[static_cast<std::size_t>(path.stroke_index(space))];
  z_ = axis(std::min(stroke.z_begin_mm, stroke.z_end_mm), std::max(stroke.z_begin_mm, stroke.z_end_mm), kStepZMm);
  for (int side = 0; side < 2; ++side) {
    const double a = map.roll_at(side, map.v_lo(side)), b = map.roll_at(side, map.v_hi(side));
    xi_[side] = axis(std::min(a, b), std::max(a, b), kStepRollMm);
  }
  std::vector<ContactVariables> at;
  at.reserve(nodes());
  for (int side = 0; side < 2; ++side)
    for (int i = 0; i < z_.n; ++i) {
      const grinding::PathPoint pp = path.point(space, z_.start + z_.step * i);
      for (int j = 0; j < xi_[side].n; ++j) {
        const double v = map.v_at_roll(side, xi_[side].start + xi_[side].step * j);
        at.push_back(map.at_side(side, v, pp, law.dressing_interval_strokes()));
      }
    }
  std::vector<double> e(at.size());
  law.deviations_um(values, at, e);
  for (std::size_t k = 0; k < e.size(); ++k)
    if (!std::isfinite(e[k])) throw NonFiniteDeviation(non_finite_message(law, e[k], at[k], values));
  const auto first_left = e.begin() + static_cast<std::ptrdiff_t>(z_.n) * xi_[0].n;
  e_um_[0].assign(e.begin(), first_left);
  e_um_[1].assign(first_left, e.end());
}

std::size_t StrokeTable::nodes() const {
  return static_cast<std::size_t>(z_.n) * static_cast<std::size_t>(xi_[0].n + xi_[1].n);
}

double StrokeTable::deviation_um(int side, double xi, double z_stroke_mm) const {
  std::array<double, 4> wz{}, wv{};
  const int i0 = z_.weights(z_stroke_mm, wz);
  const Axis& va = xi_[static_cast<std::size_t>(side)];
  const int j0 = va.weights(xi, wv);
  const auto& e = e_um_[static_cast<std::size_t>(side)];
  double sum = 0.0;
  for (int a = 0; a < 4; ++a) {
    const double* row = e.data() + static_cast<std::size_t>(i0 + a) * static_cast<std::size_t>(va.n) + j0;
    sum += wz[static_cast<std::size_t>(a)] * (wv[0] * row[0] + wv[1] * row[1] + wv[2] * row[2] + wv[3] * row[3]);
  }
  return sum;
}

} // namespace geartopo::effects
