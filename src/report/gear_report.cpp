#include "geartopo/report/gear_report.hpp"
#include "geartopo/core/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace geartopo::report {
namespace {


bool contains(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

std::string note_for(const scene::Scene& scene, const std::string& key) {
  if (contains(scene.assumed, key)) return "assumed";
  if (contains(scene.defaulted, key)) return "conventional";
  return "";
}

} // namespace

nlohmann::json gear_json(const scene::Scene& scene, const gears::GearGeometry& g) {
  const auto& s = g.spec();
  const int k = g.span_teeth();
  nlohmann::json j;
  j["name"] = scene.name;
  j["z"] = s.teeth;
  j["mn_mm"] = s.normal_module_mm;
  j["alpha_n_deg"] = s.normal_pressure_angle_rad * units::kDegPerRad;
  j["beta_deg"] = s.helix_angle_rad * units::kDegPerRad;
  j["hand"] = gears::to_string(s.hand());
  j["x"] = s.profile_shift;
  j["b_mm"] = s.face_width_mm;
  j["mt_mm"] = g.transverse_module_mm();
  j["alpha_t_deg"] = g.transverse_pressure_angle() * units::kDegPerRad;
  j["beta_b_deg"] = g.base_helix_angle() * units::kDegPerRad;
  j["d_mm"] = g.reference_diameter_mm();
  j["db_mm"] = g.base_diameter_mm();
  j["da_mm"] = g.tip_diameter_mm();
  j["df_mm"] = g.root_diameter_mm();
  j["dFf_mm"] = g.root_form_diameter_mm();
  // JSON has no infinity: a spur gear's lead is null.
  j["lead_mm"] = std::isfinite(g.lead_mm()) ? nlohmann::json(g.lead_mm()) : nlohmann::json(nullptr);
  j["pt_mm"] = g.transverse_pitch_mm();
  j["pbt_mm"] = g.transverse_base_pitch_mm();
  j["pbn_mm"] = g.normal_base_pitch_mm();
  j["sn_mm"] = g.normal_tooth_thickness_mm();
  j["st_mm"] = g.transverse_tooth_thickness_mm();
  j["san_mm"] = g.tip_normal_thickness_mm();
  j["k"] = k;
  j["Wk_mm"] = g.base_tangent_length_mm(k);
  j["dWk_mm"] = g.span_contact_diameter_mm(k);
  // The tolerance band of the inspection dimensions: the gear is made to A_sni ≤ A_sn ≤ A_sne.
  const double a_up = s.thickness_allowance_upper_mm, a_lo = s.thickness_allowance_lower_mm;
  j["A_sne_um"] = units::um_from_mm(a_up);
  j["A_sni_um"] = units::um_from_mm(a_lo);
  j["Wk_upper_mm"] = g.base_tangent_length_mm(k, a_up);
  j["Wk_lower_mm"] = g.base_tangent_length_mm(k, a_lo);
  const double ball = g.ball_diameter_mm();
  j["D_M_mm"] = ball;
  j["D_M_source"] = s.ball_diameter_mm ? "given" : "customary";
  j["MdK_mm"] = g.dimension_over_balls_mm(ball);
  j["MdK_upper_mm"] = g.dimension_over_balls_mm(ball, a_up);
  j["MdK_lower_mm"] = g.dimension_over_balls_mm(ball, a_lo);
  j["dK_mm"] = g.ball_centre_diameter_mm(ball);
  j["d_ball_contact_mm"] = g.ball_contact_diameter_mm(ball);
  j["x_min"] = g.minimum_profile_shift();
  j["d_pointed_mm"] = g.pointed_tip_diameter_mm();
  j["assumed"] = scene.assumed;
  j["conventional"] = scene.defaulted;
  j["warnings"] = g.warnings();
  return j;
}

std::string gear_table(const scene::Scene& scene, const gears::GearGeometry& g) {
  const auto& s = g.spec();
  const int k = g.span_teeth();
  std::string out;
  auto row = [&](const char* label, const char* symbol, const std::string& value, const char* unit,
                 const std::string& note = "") {
    out += fmt::format("  {:<34} {:<6} {:>14} {:<4} {}\n", label, symbol, value, unit, note);
  };
  auto num = [](double v, int digits = 4) { return fmt::format("{:.{}f}", v, digits); };

  out += fmt::format("Gear: {}\n", scene.name.empty() ? scene.source : scene.name);
  out += "Input\n";
  row("normal module", "m_n", num(s.normal_module_mm), "mm");
  row("number of teeth", "z", std::to_string(s.teeth), "");
  row("normal pressure angle", "α_n", num(s.normal_pressure_angle_rad * units::kDegPerRad), "°");
  row("helix angle", "β", num(s.helix_angle_rad * units::kDegPerRad), "°", gears::to_string(s.hand()) + std::string(" hand"));
  row("profile shift coefficient", "x", num(s.profile_shift), "");
  row("face width", "b", num(s.face_width_mm), "mm", note_for(scene, "face_width_mm"));
  row("tip diameter", "d_a", num(g.tip_diameter_mm()), "mm", note_for(scene, "tip_diameter_mm"));
  row("root diameter", "d_f", num(g.root_diameter_mm()), "mm", note_for(scene, "root_diameter_mm"));
  out += "Derived (ISO 21771)\n";
  row("transverse module", "m_t", num(g.transverse_module_mm()), "mm");
  row("transverse pressure angle", "α_t", num(g.transverse_pressure_angle() * units::kDegPerRad), "°");
  row("base helix angle", "β_b", num(g.base_helix_angle() * units::kDegPerRad), "°");
  row("reference diameter", "d", num(g.reference_diameter_mm()), "mm");
  row("base diameter", "d_b", num(g.base_diameter_mm()), "mm");
  row("root form diameter", "d_Ff", num(g.root_form_diameter_mm()), "mm",
      s.root_form_diameter_mm ? "given" : "from basic rack");
  row("lead", "p_z", std::isfinite(g.lead_mm()) ? num(g.lead_mm(), 3) : "∞", "mm");
  row("transverse pitch", "p_t", num(g.transverse_pitch_mm()), "mm");
  row("transverse base pitch", "p_bt", num(g.transverse_base_pitch_mm()), "mm");
  row("normal tooth thickness at d", "s_n", num(g.normal_tooth_thickness_mm()), "mm");
  row("normal tooth thickness at d_a", "s_an", num(g.tip_normal_thickness_mm()), "mm");
  row("teeth spanned", "k", std::to_string(k), "");
  row("base tangent length", "W_k", num(g.base_tangent_length_mm(k)), "mm",
      fmt::format("touches at d = {:.3f} mm", g.span_contact_diameter_mm(k)));
  const double a_up = s.thickness_allowance_upper_mm, a_lo = s.thickness_allowance_lower_mm;
  const double ball = g.ball_diameter_mm();
  auto band = [&](double upper_mm, double lower_mm) {
    return fmt::format("A_sne/A_sni = {:.1f}/{:.1f} µm: {:.4f} … {:.4f} mm", units::um_from_mm(a_up),
                       units::um_from_mm(a_lo), lower_mm, upper_mm);
  };
  row("base tangent length, allowed", "W_k", "", "", band(g.base_tangent_length_mm(k, a_up), g.base_tangent_length_mm(k, a_lo)));
  row("ball diameter", "D_M", num(ball), "mm", s.ball_diameter_mm ? "given" : "customary (ideal ball rounded)");
  row("dimension over balls", "M_dK", num(g.dimension_over_balls_mm(ball)), "mm",
      fmt::format("touches at d = {:.3f} mm", g.ball_contact_diameter_mm(ball)));
  row("dimension over balls, allowed", "M_dK", "", "",
      band(g.dimension_over_balls_mm(ball, a_up), g.dimension_over_balls_mm(ball, a_lo)));
  row("minimum profile shift (undercut)", "x_min", num(g.minimum_profile_shift()), "");
  row("pointed-tip diameter", "d_sa0", num(g.pointed_tip_diameter_mm()), "mm");
  for (const auto& w : g.warnings()) out += "warning: " + w + "\n";
  return out;
}

} // namespace geartopo::report
