#include "geartopo/gears/evaluation_ranges.hpp"

#include <algorithm>

namespace geartopo::gears {

EvaluationRanges iso1328_ranges(const GearGeometry& g) {
  EvaluationRanges r{};
  r.xi_active_start_mm = g.roll_length_at(g.root_form_diameter_mm());
  r.xi_active_end_mm = g.roll_length_at(g.tip_diameter_mm());
  r.xi_eval_start_mm = r.xi_active_start_mm;
  r.xi_eval_end_mm = r.xi_active_start_mm + 0.95 * (r.xi_active_end_mm - r.xi_active_start_mm);
  const double b = g.spec().face_width_mm;
  const double trim = std::min(0.05 * b, g.spec().normal_module_mm);
  r.z_eval_start_mm = trim;
  r.z_eval_end_mm = b - trim;
  return r;
}

} // namespace geartopo::gears
