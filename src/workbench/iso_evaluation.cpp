// geartopo — topologies into the ISO 1328-1 evaluator. Units: µm (deviations, along the normal in, as asked out), mm.
#include "geartopo/workbench/iso_evaluation.hpp"

#include <numbers>

namespace geartopo::workbench {
namespace {


// Deviation at z along a helix trace (linear interpolation; the trace covers the face width).
double at_z(const std::vector<grinding::TracePoint>& helix, double z) {
  for (size_t i = 1; i < helix.size(); ++i)
    if (helix[i].z_mm >= z) {
      const auto &a = helix[i - 1], &b = helix[i];
      const double t = (z - a.z_mm) / (b.z_mm - a.z_mm);
      return a.deviation_um + t * (b.deviation_um - a.deviation_um);
    }
  return helix.back().deviation_um;
}

} // namespace

evaluation::GearParameters gear_parameters(const gears::GearGeometry& g) {
  return {g.teeth(), g.reference_diameter_mm(), g.spec().normal_module_mm, g.spec().face_width_mm, g.spec().helix_angle_rad};
}

evaluation::IsoConventions iso_conventions(const gears::GearGeometry& g, const IsoOptions& o) {
  return {o.direction, o.helix_slope_sign, g.base_helix_angle()};
}

evaluation::GearMeasurement gear_measurement(const gears::GearGeometry& g, const gears::EvaluationRanges& r,
                                             const std::vector<grinding::FlankTopology>& topo, const IsoOptions& o) {
  evaluation::GearMeasurement m;
  m.conventions = iso_conventions(g, o);
  double d_m = 0.0;
  for (const auto& ft : topo) {
    evaluation::FlankMeasurement fm;
    fm.tooth = ft.tooth;
    fm.side = ft.flank;
    for (const auto& p : ft.profile) fm.profile.position_mm.push_back(p.roll_length_mm), fm.profile.deviation_um.push_back(p.deviation_um);
    fm.profile.range_start_mm = r.xi_eval_start_mm;
    fm.profile.range_end_mm = r.xi_eval_end_mm;
    for (const auto& p : ft.helix) fm.helix.position_mm.push_back(p.z_mm), fm.helix.deviation_um.push_back(p.deviation_um);
    fm.helix.range_start_mm = r.z_eval_start_mm;
    fm.helix.range_end_mm = r.z_eval_end_mm;
    m.flanks.push_back(std::move(fm));
    if (!ft.helix.empty()) {
      m.pitch_points.push_back({ft.tooth, ft.flank, at_z(ft.helix, 0.5 * g.spec().face_width_mm)});
      d_m = ft.helix.front().diameter_mm;
    }
  }
  if (d_m > 0.0) {
    evaluation::PitchGeometry pg;
    pg.base_helix_angle_rad = g.base_helix_angle();
    pg.transverse_pressure_angle_rad = g.transverse_pressure_angle_at(d_m);
    pg.space_half_angle_rad = std::numbers::pi / g.teeth() - g.transverse_tooth_thickness_at(d_m) / d_m;
    m.pitch_geometry = pg;
  }
  return m;
}

IsoResult evaluate_iso(const gears::GearGeometry& g, const gears::EvaluationRanges& r,
                       const std::vector<grinding::FlankTopology>& topo, const IsoOptions& o) {
  IsoResult res{gear_parameters(g), {}, {}};
  res.evaluation = evaluation::evaluate_gear(gear_measurement(g, r, topo, o), res.parameters);
  for (const auto& ft : topo) {
    std::vector<evaluation::TwistGridPoint> grid;
    for (const auto& p : ft.grid) grid.push_back({p.row, p.col, p.roll_length_mm, p.z_mm, p.deviation_um});
    if (grid.size() >= 4) res.twists.push_back({ft.tooth, ft.flank, evaluation::flank_twist(grid)});
  }
  return res;
}

} // namespace geartopo::workbench
