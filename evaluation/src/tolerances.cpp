// geartopo evaluation — ISO 1328-1:2013 tolerances and classes. Units: mm (gear data), µm (tolerances), rad (β).
#include "geartopo/evaluation/tolerances.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace geartopo::evaluation {

namespace {

void require_valid(const GearParameters& p) {
  if (auto why = validity_refusal(p)) throw std::domain_error("ISO 1328-1 tolerances refused: " + *why);
}

void require_class(int a) {
  if (a < kFinestClass || a > kCoarsestClass)
    throw std::invalid_argument(fmt::format("flank tolerance class {} is outside 1..11", a));
}

} // namespace

std::string_view symbol(Quantity q) {
  switch (q) {
  case Quantity::SinglePitch: return "f_p";
  case Quantity::CumulativePitch: return "F_p";
  case Quantity::ProfileSlope: return "f_Hα";
  case Quantity::ProfileForm: return "f_fα";
  case Quantity::ProfileTotal: return "F_α";
  case Quantity::HelixSlope: return "f_Hβ";
  case Quantity::HelixForm: return "f_fβ";
  case Quantity::HelixTotal: return "F_β";
  case Quantity::Runout: return "F_r";
  }
  return "?";
}

std::optional<std::string> validity_refusal(const GearParameters& p) {
  std::vector<std::string> why;
  if (p.teeth < 5 || p.teeth > 1000) why.push_back(fmt::format("z = {} is outside 5..1000", p.teeth));
  const auto in = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  if (!in(p.reference_diameter_mm, 5.0, 15000.0))
    why.push_back(fmt::format("d = {} mm is outside 5..15000 mm", p.reference_diameter_mm));
  if (!in(p.normal_module_mm, 0.5, 70.0))
    why.push_back(fmt::format("m_n = {} mm is outside 0.5..70 mm", p.normal_module_mm));
  if (!in(p.face_width_mm, 4.0, 1200.0))
    why.push_back(fmt::format("b = {} mm is outside 4..1200 mm", p.face_width_mm));
  const double beta_deg = p.helix_angle_rad * 180.0 / std::numbers::pi;
  // 1e-9° slack so that 45° converted to radians and back is not refused.
  if (!std::isfinite(beta_deg) || std::abs(beta_deg) > 45.0 + 1e-9)
    why.push_back(fmt::format("|β| = {:.6g}° exceeds 45°", std::abs(beta_deg)));
  if (why.empty()) return std::nullopt;
  std::string s = why.front();
  for (std::size_t i = 1; i < why.size(); ++i) s += "; " + why[i];
  return s + " (ISO 1328-1:2013 range of validity; tolerances are not to be extrapolated)";
}

std::string class_label(const std::optional<int>& c) { return c ? class_label(*c) : "–"; }

std::string class_label(int a) {
  if (a >= kFinestClass && a <= kCoarsestClass) return std::to_string(a);
  if (a == kWorseThanClass11) return "worse than 11";
  return fmt::format("invalid class {}", a);
}

double round_tolerance_um(double x) {
  if (!std::isfinite(x) || x < 0.0)
    throw std::invalid_argument(fmt::format("cannot round tolerance {} µm", x));
  constexpr double tie_slack = 1e-9; // in units of the rounding step
  if (x > 10.0) return std::floor(x + 0.5 + tie_slack);
  if (x >= 5.0) return std::floor(2.0 * x + 0.5 + tie_slack) / 2.0;
  return std::floor(10.0 * x + 0.5 + tie_slack) / 10.0; // n / 10 is the double nearest the decimal n/10
}

double class5_tolerance_um(Quantity q, const GearParameters& p) {
  require_valid(p);
  const double d = p.reference_diameter_mm, m = p.normal_module_mm, b = p.face_width_mm;
  const double fHa = 0.4 * m + 0.001 * d + 4.0;
  const double ffa = 0.55 * m + 5.0;
  const double fHb = 0.05 * std::sqrt(d) + 0.35 * std::sqrt(b) + 4.0;
  const double ffb = 0.07 * std::sqrt(d) + 0.45 * std::sqrt(b) + 4.0;
  const double Fp = 0.002 * d + 0.55 * std::sqrt(d) + 0.7 * m + 12.0;
  switch (q) {
  case Quantity::SinglePitch: return 0.001 * d + 0.4 * m + 5.0;
  case Quantity::CumulativePitch: return Fp;
  case Quantity::ProfileSlope: return fHa;
  case Quantity::ProfileForm: return ffa;
  case Quantity::ProfileTotal: return std::hypot(fHa, ffa);
  case Quantity::HelixSlope: return fHb;
  case Quantity::HelixForm: return ffb;
  case Quantity::HelixTotal: return std::hypot(fHb, ffb);
  case Quantity::Runout: return 0.9 * Fp;
  }
  throw std::invalid_argument("unknown quantity");
}

double unrounded_tolerance_um(Quantity q, const GearParameters& p, int a) {
  require_class(a);
  return class5_tolerance_um(q, p) * std::pow(std::numbers::sqrt2, a - 5);
}

double tolerance_um(Quantity q, const GearParameters& p, int a) {
  return round_tolerance_um(unrounded_tolerance_um(q, p, a));
}

double ToleranceSet::of(Quantity q) const {
  switch (q) {
  case Quantity::SinglePitch: return f_pT_um;
  case Quantity::CumulativePitch: return F_pT_um;
  case Quantity::ProfileSlope: return f_HalphaT_um;
  case Quantity::ProfileForm: return f_falphaT_um;
  case Quantity::ProfileTotal: return F_alphaT_um;
  case Quantity::HelixSlope: return f_HbetaT_um;
  case Quantity::HelixForm: return f_fbetaT_um;
  case Quantity::HelixTotal: return F_betaT_um;
  case Quantity::Runout: return F_rT_um;
  }
  throw std::invalid_argument("unknown quantity");
}

ToleranceSet tolerances(const GearParameters& p, int a) {
  ToleranceSet t;
  t.flank_class = a;
  t.f_pT_um = tolerance_um(Quantity::SinglePitch, p, a);
  t.F_pT_um = tolerance_um(Quantity::CumulativePitch, p, a);
  t.f_HalphaT_um = tolerance_um(Quantity::ProfileSlope, p, a);
  t.f_falphaT_um = tolerance_um(Quantity::ProfileForm, p, a);
  t.F_alphaT_um = tolerance_um(Quantity::ProfileTotal, p, a);
  t.f_HbetaT_um = tolerance_um(Quantity::HelixSlope, p, a);
  t.f_fbetaT_um = tolerance_um(Quantity::HelixForm, p, a);
  t.F_betaT_um = tolerance_um(Quantity::HelixTotal, p, a);
  t.F_rT_um = tolerance_um(Quantity::Runout, p, a);
  return t;
}

int tolerance_class(Quantity q, double value_um, const GearParameters& p) {
  require_valid(p);
  if (!std::isfinite(value_um)) throw std::invalid_argument(fmt::format("cannot classify {} µm", value_um));
  const double v = std::abs(value_um);
  for (int a = kFinestClass; a <= kCoarsestClass; ++a)
    if (tolerance_um(q, p, a) >= v) return a;
  return kWorseThanClass11;
}

} // namespace geartopo::evaluation
