#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/core/field_error.hpp"
#include "geartopo/gears/involute.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <numbers>

namespace geartopo::gears {
namespace {

constexpr double kPi = std::numbers::pi;

void require(bool ok, const char* field, const std::string& message) {
  if (!ok) throw FieldError(field, message);
}

void validate_inputs(const GearSpec& s) {
  auto finite = [](double v) { return std::isfinite(v); };
  require(finite(s.normal_module_mm) && s.normal_module_mm > 0.0, "gear.normal_module_mm",
          fmt::format("{} mm must be > 0", s.normal_module_mm));
  require(s.teeth >= 5, "gear.teeth", fmt::format("{} teeth is degenerate: at least 5 are needed", s.teeth));
  require(s.teeth <= 10000, "gear.teeth", fmt::format("{} teeth is beyond 10000", s.teeth));
  require(finite(s.normal_pressure_angle_rad) && s.normal_pressure_angle_rad > 5 * units::kRadPerDeg &&
              s.normal_pressure_angle_rad < 45 * units::kRadPerDeg,
          "gear.normal_pressure_angle_deg",
          fmt::format("{:.4g}° must lie strictly between 5° and 45°", s.normal_pressure_angle_rad * units::kDegPerRad));
  require(finite(s.helix_angle_rad) && std::abs(s.helix_angle_rad) < 45 * units::kRadPerDeg - 1e-12, "gear.helix_angle_deg",
          fmt::format("|{:.4g}°| must be below 45°", s.helix_angle_rad * units::kDegPerRad));
  require(finite(s.profile_shift) && std::abs(s.profile_shift) <= 3.0, "gear.profile_shift",
          fmt::format("{} is outside [-3, 3]", s.profile_shift));
  require(finite(s.face_width_mm) && s.face_width_mm > 0.0, "gear.face_width_mm",
          fmt::format("{} mm must be > 0", s.face_width_mm));
  require(finite(s.rack_dedendum_coef) && s.rack_dedendum_coef > 0.0, "gear.rack_dedendum_coef",
          fmt::format("{} must be > 0", s.rack_dedendum_coef));
  require(finite(s.rack_root_radius_coef) && s.rack_root_radius_coef >= 0.0, "gear.rack_root_radius_coef",
          fmt::format("{} must be >= 0", s.rack_root_radius_coef));
  require(finite(s.tip_diameter_mm) && s.tip_diameter_mm > 0.0, "gear.tip_diameter_mm",
          fmt::format("{} mm must be > 0", s.tip_diameter_mm));
  require(finite(s.root_diameter_mm) && s.root_diameter_mm > 0.0, "gear.root_diameter_mm",
          fmt::format("{} mm must be > 0", s.root_diameter_mm));
  require(finite(s.thickness_allowance_upper_mm), "gear.thickness_allowance_upper_um", "must be finite");
  require(finite(s.thickness_allowance_lower_mm), "gear.thickness_allowance_lower_um", "must be finite");
  require(s.thickness_allowance_upper_mm >= s.thickness_allowance_lower_mm, "gear.thickness_allowance_lower_um",
          fmt::format("{} µm is above the upper allowance {} µm", units::um_from_mm(s.thickness_allowance_lower_mm),
                      units::um_from_mm(s.thickness_allowance_upper_mm)));
  if (s.ball_diameter_mm)
    require(finite(*s.ball_diameter_mm) && *s.ball_diameter_mm > 0.0, "gear.ball_diameter_mm",
            fmt::format("{} mm must be > 0", *s.ball_diameter_mm));
  require(s.root_diameter_mm < s.tip_diameter_mm, "gear.root_diameter_mm",
          fmt::format("{} mm must be below the tip diameter {} mm", s.root_diameter_mm, s.tip_diameter_mm));
}

} // namespace

GearGeometry::GearGeometry(const GearSpec& spec) : spec_(spec) {
  validate_inputs(spec_);
  const double mn = spec_.normal_module_mm;
  const double an = spec_.normal_pressure_angle_rad;
  const double beta = spec_.helix_angle_rad;
  const double x = spec_.profile_shift;
  const int z = spec_.teeth;

  mt_ = mn / std::cos(beta);
  alpha_t_ = std::atan(std::tan(an) / std::cos(beta));
  beta_b_ = std::asin(std::sin(beta) * std::cos(an));
  d_ = z * mt_;
  db_ = d_ * std::cos(alpha_t_);
  twist_ = 2.0 * std::tan(beta) / d_;
  pt_ = kPi * mt_;
  pbt_ = kPi * db_ / z;
  sn_ = mn * (kPi / 2.0 + 2.0 * x * std::tan(an));
  st_ = sn_ / std::cos(beta);
  psi_b_ = st_ / d_ + involute(alpha_t_);

  // Basic rack: its straight flank ends h_FfP below the datum line, where the root radius ρ_fP begins.
  const double h_ffp = (spec_.rack_dedendum_coef - spec_.rack_root_radius_coef * (1.0 - std::sin(an))) * mn;
  const double sin_at = std::sin(alpha_t_);
  x_min_ = h_ffp / mn - z * sin_at * sin_at / (2.0 * std::cos(beta));
  const double xi_ff_rack = 0.5 * d_ * sin_at - (h_ffp - x * mn) / sin_at; // roll length where generation ends

  if (spec_.root_form_diameter_mm) {
    dFf_ = *spec_.root_form_diameter_mm;
    require(std::isfinite(dFf_) && dFf_ >= db_, "gear.root_form_diameter_mm",
            fmt::format("{:.4f} mm is below the base diameter {:.4f} mm: there is no involute there", dFf_, db_));
  } else {
    require(x >= x_min_ - 1e-9, "gear.profile_shift",
            fmt::format("x = {} is below x_min = {:.4f} for z = {}: the basic rack undercuts the involute "
                        "(raise the profile shift or give gear.root_form_diameter_mm)",
                        x, x_min_, z));
    dFf_ = 2.0 * std::hypot(0.5 * db_, std::max(xi_ff_rack, 0.0));
  }
  require(dFf_ > spec_.root_diameter_mm, "gear.root_diameter_mm",
          fmt::format("{:.4f} mm reaches above the root form diameter d_Ff = {:.4f} mm", spec_.root_diameter_mm, dFf_));
  require(dFf_ < spec_.tip_diameter_mm, "gear.tip_diameter_mm",
          fmt::format("{:.4f} mm is not above the root form diameter d_Ff = {:.4f} mm: no involute flank is left",
                      spec_.tip_diameter_mm, dFf_));

  d_pointed_ = db_ / std::cos(inverse_involute(psi_b_));
  require(spec_.tip_diameter_mm < d_pointed_, "gear.tip_diameter_mm",
          fmt::format("{:.4f} mm is at or beyond the pointed-tip diameter {:.4f} mm (tooth thickness 0 there)",
                      spec_.tip_diameter_mm, d_pointed_));
  const double s_an = tip_normal_thickness_mm();
  if (s_an < 0.25 * mn)
    warnings_.push_back(fmt::format("thin tip: normal tooth thickness at the tip {:.3f} mm is below 0.25 m_n = {:.3f} mm",
                                    s_an, 0.25 * mn));

  // Customary span (DIN 3960): the caliper should touch near d_M = d + 2 x m_n.
  const double dM = d_ + 2.0 * x * mn;
  const double alpha_m = std::acos(std::min(1.0, db_ / dM));
  const double cb = std::cos(beta_b_);
  const double k_real = z / kPi * (std::tan(alpha_m) / (cb * cb) - 2.0 * x * std::tan(an) / z - involute(alpha_t_)) + 0.5;
  k_ = std::clamp(static_cast<int>(std::lround(k_real)), 1, z - 1);

  require(sn_ + spec_.thickness_allowance_lower_mm > 0.0, "gear.thickness_allowance_lower_um",
          fmt::format("{} µm leaves no tooth: the normal tooth thickness is {:.4f} mm",
                      units::um_from_mm(spec_.thickness_allowance_lower_mm), sn_));
  ball_ = spec_.ball_diameter_mm ? *spec_.ball_diameter_mm : customary_ball_diameter_mm();
  // Checks the ball at both ends of the tolerance band (throws when it drops inside the base cylinder) and warns
  // when it touches outside the involute: the formula then describes no real measurement.
  for (const double a : {spec_.thickness_allowance_upper_mm, spec_.thickness_allowance_lower_mm}) {
    const double dc = ball_contact_diameter_mm(ball_, a);
    if (dc < dFf_ || dc > spec_.tip_diameter_mm) {
      warnings_.push_back(fmt::format("ball D_M = {:.4f} mm touches at d = {:.4f} mm (A_sn = {} µm), outside the "
                                      "involute [{:.4f}, {:.4f}] mm: M_dK is not measurable with it",
                                      ball_, dc, units::um_from_mm(a), dFf_, spec_.tip_diameter_mm));
      break;
    }
  }
}

double GearGeometry::lead_mm() const {
  if (spec_.helix_angle_rad == 0.0) return std::numeric_limits<double>::infinity();
  return kPi * d_ / std::tan(spec_.helix_angle_rad);
}

double GearGeometry::transverse_pressure_angle_at(double dy) const {
  if (!(dy >= db_)) throw std::domain_error(fmt::format("diameter {} mm is below the base diameter {} mm", dy, db_));
  return std::acos(db_ / dy);
}

double GearGeometry::transverse_tooth_thickness_at(double dy) const {
  return dy * (psi_b_ - involute(transverse_pressure_angle_at(dy)));
}

double GearGeometry::normal_tooth_thickness_at(double dy) const {
  const double beta_y = std::atan(std::tan(spec_.helix_angle_rad) * dy / d_);
  return transverse_tooth_thickness_at(dy) * std::cos(beta_y);
}

double GearGeometry::roll_length_at(double dy) const {
  if (!(dy >= db_)) throw std::domain_error(fmt::format("diameter {} mm is below the base diameter {} mm", dy, db_));
  return 0.5 * std::sqrt(dy * dy - db_ * db_);
}

double GearGeometry::diameter_at_roll_length(double xi) const { return 2.0 * std::hypot(0.5 * db_, xi); }

double GearGeometry::base_tangent_length_mm(int k, double thickness_allowance_mm) const {
  const double mn = spec_.normal_module_mm, an = spec_.normal_pressure_angle_rad;
  return mn * std::cos(an) * ((k - 0.5) * kPi + spec_.teeth * involute(alpha_t_)) +
         2.0 * spec_.profile_shift * mn * std::sin(an) + thickness_allowance_mm * std::cos(an);
}

double GearGeometry::ball_centre_diameter_mm(double D, double a_sn) const {
  const double mn = spec_.normal_module_mm, an = spec_.normal_pressure_angle_rad;
  const int z = spec_.teeth;
  const double inv_mt = involute(alpha_t_) + D / (mn * z * std::cos(an)) + (sn_ + a_sn) / (mn * z) - kPi / z;
  require(std::isfinite(D) && D > 0.0 && inv_mt > 0.0, "gear.ball_diameter_mm",
          fmt::format("{:.4f} mm is too small: the ball would sit inside the base circle (d_b = {:.4f} mm)", D, db_));
  return db_ / std::cos(inverse_involute(inv_mt));
}

double GearGeometry::dimension_over_balls_mm(double D, double a_sn) const {
  const double dk = ball_centre_diameter_mm(D, a_sn);
  const int z = spec_.teeth;
  return (z % 2 == 0 ? dk : dk * std::cos(0.5 * kPi / z)) + D;
}

double GearGeometry::ball_contact_diameter_mm(double D, double a_sn) const {
  const double rb = 0.5 * db_;
  const double xi_centre = std::sqrt(std::max(0.0, 0.25 * std::pow(ball_centre_diameter_mm(D, a_sn), 2) - rb * rb));
  return diameter_at_roll_length(std::max(0.0, xi_centre - 0.5 * D * std::cos(beta_b_)));
}

double GearGeometry::ideal_ball_diameter_mm() const {
  const double mn = spec_.normal_module_mm;
  const double target = d_ + 2.0 * spec_.profile_shift * mn;
  // The contact diameter grows monotonically with D_M; bracket generously around the tabled 1.7 m_n.
  double lo = 0.2 * mn, hi = 4.0 * mn;
  auto contact = [&](double D) {
    // Below the smallest possible ball the formula has no solution: treat it as touching at the base circle.
    try {
      return ball_contact_diameter_mm(D, 0.0);
    } catch (const FieldError&) {
      return db_;
    }
  };
  if (contact(lo) > target) return lo;
  if (contact(hi) < target) return hi;
  for (int i = 0; i < 100 && hi - lo > 1e-10 * mn; ++i) {
    const double mid = 0.5 * (lo + hi);
    (contact(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double GearGeometry::customary_ball_diameter_mm() const {
  const double ideal = ideal_ball_diameter_mm();
  const double step = ideal < 1.0 ? 0.01 : 0.05;
  return std::max(step, std::round(ideal / step) * step);
}

double GearGeometry::span_contact_diameter_mm(int k) const {
  return diameter_at_roll_length(0.5 * base_tangent_length_mm(k) * std::cos(beta_b_));
}

} // namespace geartopo::gears
