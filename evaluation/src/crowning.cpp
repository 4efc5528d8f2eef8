// Crowning of a trace: height of its least-squares parabola above the chord over the evaluation range.

#include "geartopo/evaluation/crowning.hpp"

#include <Eigen/Dense>

#include <stdexcept>

namespace geartopo::evaluation {

double crowning_um(const Trace& trace) {
  evaluate_trace(trace); // the same input checks and messages as F, f_f, f_H
  const double mid = 0.5 * (trace.range_start_mm + trace.range_end_mm);
  const double half = 0.5 * (trace.range_end_mm - trace.range_start_mm);
  // Rows: points inside the range; columns 1, t, t² with t = (s − mid)/half in [−1, 1] (well conditioned).
  std::vector<Eigen::Index> inside;
  for (std::size_t i = 0; i < trace.position_mm.size(); ++i)
    if (trace.position_mm[i] >= trace.range_start_mm - kRangeSlackMm && trace.position_mm[i] <= trace.range_end_mm + kRangeSlackMm)
      inside.push_back(static_cast<Eigen::Index>(i));
  if (inside.size() < 3) throw std::invalid_argument("crowning: fewer than 3 points inside the evaluation range");
  Eigen::MatrixXd A(static_cast<Eigen::Index>(inside.size()), 3); // n × 3
  Eigen::VectorXd d(A.rows());                                     // n
  for (Eigen::Index r = 0; r < A.rows(); ++r) {
    const auto i = static_cast<std::size_t>(inside[static_cast<std::size_t>(r)]);
    const double t = (trace.position_mm[i] - mid) / half;
    A.row(r) << 1.0, t, t * t;
    d(r) = trace.deviation_um[i];
  }
  const Eigen::Vector3d coef = A.colPivHouseholderQr().solve(d);
  // Parabola in t: a + b t + c t²; at t = 0 it is a, the chord through t = ±1 is a + c there: height −c.
  return -coef(2);
}

} // namespace geartopo::evaluation
