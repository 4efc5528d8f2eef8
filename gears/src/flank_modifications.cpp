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
  }
}

double FlankDesign::profile_um(geartopo::Flank flank, double xi) const {
  const Side& s = side(flank);
  const auto& m = s.m;
  if (!m.has_profile()) return 0.0;
  const double u = (xi - xi_m_) / l_alpha_; // −½ … ½ over L_α
  double v = -m.profile_crowning_um * 4.0 * u * u + m.profile_slope_um * u;
  if (m.tip_relief_um != 0.0 && xi > s.xi_tip_relief)
    v -= m.tip_relief_um * shape(m.tip_relief_shape, (xi - s.xi_tip_relief) / (xi_a_ - s.xi_tip_relief));
  if (m.root_relief_um != 0.0 && xi < s.xi_root_relief)
    v -= m.root_relief_um * shape(m.root_relief_shape, (s.xi_root_relief - xi) / (s.xi_root_relief - xi_ff_));
  return v;
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
