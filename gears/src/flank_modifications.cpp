#include "geartopo/gears/flank_modifications.hpp"

#include "geartopo/core/field_error.hpp"
#include "geartopo/gears/evaluation_ranges.hpp"
#include "geartopo/gears/gear_geometry.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace geartopo::gears {
namespace {

/// The relief's depth fraction at t ∈ [0, 1] from its start: linear, or the arc's parabola tangent at the start.
double shape(ReliefShape s, double t) {
  t = std::clamp(t, 0.0, 1.0);
  return s == ReliefShape::Arc ? t * t : t;
}

} // namespace

bool FlankModifications::has_profile() const {
  return profile_crowning_um != 0.0 || profile_slope_um != 0.0 || tip_relief_um != 0.0 || root_relief_um != 0.0;
}

bool FlankModifications::has_helix() const {
  return helix_crowning_um != 0.0 || helix_slope_um != 0.0 || end_relief_um != 0.0;
}

FlankDesign::FlankDesign(const GearGeometry& g, const EvaluationRanges& r, const DesignModifications& mods)
    : mods_(mods),
      xi_m_(0.5 * (r.xi_eval_start_mm + r.xi_eval_end_mm)),
      l_alpha_(r.profile_evaluation_length()),
      xi_ff_(r.xi_active_start_mm),
      xi_a_(r.xi_active_end_mm),
      z_m_(0.5 * (r.z_eval_start_mm + r.z_eval_end_mm)),
      l_beta_(r.helix_evaluation_length()),
      face_(g.spec().face_width_mm) {
  const double d_ff = g.root_form_diameter_mm(), d_a = g.tip_diameter_mm();
  for (auto f : {geartopo::Flank::Left, geartopo::Flank::Right}) {
    Side& s = f == geartopo::Flank::Left ? left_ : right_;
    s.m = mods.of(f);
    // The scene key the values came from: `both` when the two flanks are alike.
    const std::string key = fmt::format("gear.modifications.{}.", mods.left == mods.right ? "both" : to_string(f));
    // A relief starts strictly inside the active profile d_Ff … d_a, so that it has a length to run over.
    const auto start_inside = [&](double amount_um, double d_mm, const char* name) {
      if (amount_um == 0.0) return;
      if (!(d_mm > d_ff && d_mm < d_a))
        throw FieldError(key + name, fmt::format("{} mm is outside the active profile: the relief must start between the "
                                                 "root form diameter d_Ff = {:.3f} mm and the tip diameter d_a = {:.3f} mm",
                                                 d_mm, d_ff, d_a));
    };
    start_inside(s.m.tip_relief_um, s.m.tip_relief_start_diameter_mm, "tip_relief_start_diameter_mm");
    start_inside(s.m.root_relief_um, s.m.root_relief_start_diameter_mm, "root_relief_start_diameter_mm");
    if (s.m.tip_relief_um != 0.0 && s.m.root_relief_um != 0.0 &&
        !(s.m.root_relief_start_diameter_mm < s.m.tip_relief_start_diameter_mm))
      throw FieldError(key + "root_relief_start_diameter_mm",
                       fmt::format("{} mm is not below the tip relief's start {} mm: the two reliefs overlap",
                                   s.m.root_relief_start_diameter_mm, s.m.tip_relief_start_diameter_mm));
    if (s.m.end_relief_um != 0.0 && !(s.m.end_relief_length_mm > 0.0 && s.m.end_relief_length_mm < 0.5 * face_))
      throw FieldError(key + "end_relief_length_mm",
                       fmt::format("{} mm is outside the face width: an end relief runs over more than 0 and less than "
                                   "half the face width b/2 = {} mm from each end",
                                   s.m.end_relief_length_mm, 0.5 * face_));
    if (s.m.tip_relief_um != 0.0) s.xi_tip_relief = g.roll_length_at(s.m.tip_relief_start_diameter_mm);
    if (s.m.root_relief_um != 0.0) s.xi_root_relief = g.roll_length_at(s.m.root_relief_start_diameter_mm);
    const auto& grid = mods.table.of(f);
    if (grid.empty()) continue;
    // The table must cover the evaluation ranges (1 µm of slack for diameters written to a few decimals).
    const std::string where = fmt::format("{} flank of {}", to_string(f), mods.table.file);
    const double d_lo = g.diameter_at_roll_length(r.xi_eval_start_mm), d_hi = g.diameter_at_roll_length(r.xi_eval_end_mm);
    if (grid.diameter_mm.front() > d_lo + 1e-3 || grid.diameter_mm.back() < d_hi - 1e-3)
      throw FieldError("gear.modifications.table",
                       fmt::format("the {} covers diameters {:.3f} … {:.3f} mm; the profile evaluation range L_α needs "
                                   "{:.3f} … {:.3f} mm",
                                   where, grid.diameter_mm.front(), grid.diameter_mm.back(), d_lo, d_hi));
    if (grid.z_mm.front() > r.z_eval_start_mm + 1e-3 || grid.z_mm.back() < r.z_eval_end_mm - 1e-3)
      throw FieldError("gear.modifications.table",
                       fmt::format("the {} covers z {:.3f} … {:.3f} mm; the helix evaluation range L_β needs {:.3f} … "
                                   "{:.3f} mm",
                                   where, grid.z_mm.front(), grid.z_mm.back(), r.z_eval_start_mm, r.z_eval_end_mm));
    if (grid.diameter_mm.front() < g.base_diameter_mm())
      throw FieldError("gear.modifications.table", fmt::format("the {} starts at d = {:.3f} mm, below the base "
                                                               "diameter d_b = {:.3f} mm",
                                                               where, grid.diameter_mm.front(), g.base_diameter_mm()));
    for (double d : grid.diameter_mm) s.table_xi_mm.push_back(g.roll_length_at(d));
  }
}

double FlankDesign::table_um(geartopo::Flank flank, double xi, double z) const {
  const Side& s = side(flank);
  if (s.table_xi_mm.empty()) return 0.0;
  const auto& grid = mods_.table.of(flank);
  // Bilinear in (ξ, z), constant beyond the edges: the cell and the fraction along each direction.
  const auto cell = [](const std::vector<double>& knots, double x) {
    if (x <= knots.front()) return std::pair<size_t, double>{0, 0.0};
    if (x >= knots.back()) return std::pair<size_t, double>{knots.size() - 2, 1.0};
    const size_t k = static_cast<size_t>(std::upper_bound(knots.begin(), knots.end(), x) - knots.begin()) - 1;
    return std::pair<size_t, double>{k, (x - knots[k]) / (knots[k + 1] - knots[k])};
  };
  const auto [i, u] = cell(s.table_xi_mm, xi);
  const auto [j, v] = cell(grid.z_mm, z);
  const size_t nz = grid.z_mm.size();
  const auto at = [&](size_t a, size_t b) { return grid.value_um[a * nz + b]; };
  return (1 - u) * ((1 - v) * at(i, j) + v * at(i, j + 1)) + u * ((1 - v) * at(i + 1, j) + v * at(i + 1, j + 1));
}

double FlankDesign::motion_target_um(geartopo::Flank flank, double xi, double z) const {
  return helix_um(flank, z) + table_um(flank, xi, z) - table_um(flank, xi, z_m_);
}

double FlankDesign::profile_um(geartopo::Flank flank, double xi) const {
  const Side& s = side(flank);
  const auto& m = s.m;
  const double table = table_um(flank, xi, z_m_);
  if (!m.has_profile()) return table;
  const double u = (xi - xi_m_) / l_alpha_; // −½ … ½ over L_α
  double v = -m.profile_crowning_um * 4.0 * u * u + m.profile_slope_um * u;
  if (m.tip_relief_um != 0.0 && xi > s.xi_tip_relief)
    v -= m.tip_relief_um * shape(m.tip_relief_shape, (xi - s.xi_tip_relief) / (xi_a_ - s.xi_tip_relief));
  if (m.root_relief_um != 0.0 && xi < s.xi_root_relief)
    v -= m.root_relief_um * shape(m.root_relief_shape, (s.xi_root_relief - xi) / (s.xi_root_relief - xi_ff_));
  return v + table;
}

double FlankDesign::helix_um(geartopo::Flank flank, double z) const {
  const auto& m = side(flank).m;
  if (!m.has_helix()) return 0.0;
  const double u = (z - z_m_) / l_beta_;
  double v = -m.helix_crowning_um * 4.0 * u * u + m.helix_slope_um * u;
  if (m.end_relief_um != 0.0) {
    const double l = m.end_relief_length_mm, to_end = std::min(z, face_ - z);
    if (to_end < l) v -= m.end_relief_um * shape(m.end_relief_shape, (l - to_end) / l);
  }
  return v;
}

const char* to_string(ReliefShape shape) { return shape == ReliefShape::Arc ? "arc" : "linear"; }

} // namespace geartopo::gears
