// geartopo evaluation — gear-level evaluation and classification. Units: mm, µm, rad.
#include "geartopo/evaluation/gear_evaluation.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace geartopo::evaluation {

namespace {

/// Index of a flank in per-flank tables of size 2z.
std::size_t slot(int tooth, Flank side) { return static_cast<std::size_t>(tooth - 1) * 2 + (side == Flank::Right ? 1 : 0); }

void check_tooth(int tooth, int z, const char* what) {
  if (tooth < 1 || tooth > z)
    throw std::invalid_argument(fmt::format("{}: tooth {} is outside 1..{}", what, tooth, z));
}

std::string flank_name(int tooth, Flank side) { return fmt::format("tooth {} {}", tooth, to_string(side)); }

/// Keeps the occurrence with the largest |value| of each quantity.
struct Worst {
  std::vector<QuantityClass> list;
  void add(Quantity q, double v, const std::string& where) {
    for (auto& e : list)
      if (e.quantity == q) {
        if (std::abs(v) > std::abs(e.worst_value_um)) {
          e.worst_value_um = v;
          e.where = where;
        }
        return;
      }
    list.push_back({q, v, where, std::nullopt});
  }
};

/// Scales every value of a trace evaluation (all are linear in the deviations).
void scale(TraceDeviations& t, double k) {
  t.total_um *= k;
  t.form_um *= k;
  t.slope_um *= k;
  t.mean_line_mid_um *= k;
  t.mean_line_slope_um_per_mm *= k;
}

} // namespace

std::string_view to_string(IsoDirection d) { return d == IsoDirection::Transverse ? "transverse" : "normal"; }

std::optional<IsoDirection> parse_iso_direction(std::string_view w) {
  if (w == "transverse") return IsoDirection::Transverse;
  if (w == "normal") return IsoDirection::Normal;
  return std::nullopt;
}

std::string_view to_string(HelixSlopeSign s) {
  return s == HelixSlopeSign::HelixAngle ? "helix-angle" : "rise-towards-plus-z";
}

std::optional<HelixSlopeSign> parse_helix_slope_sign(std::string_view w) {
  if (w == "helix-angle") return HelixSlopeSign::HelixAngle;
  if (w == "rise-towards-plus-z") return HelixSlopeSign::RiseTowardsPlusZ;
  return std::nullopt;
}

std::string describe(const IsoConventions& c) {
  const std::string dir = c.direction == IsoDirection::Transverse
                              ? fmt::format("transverse (ISO 1328-1: profile ⟂ involute and helix along the base-circle "
                                            "tangent, in the transverse plane; = normal / cos β_b = normal × {:.4f})",
                                            reported_per_normal(c))
                              : std::string("normal (along the flank normal)");
  const std::string sign = c.helix_slope_sign == HelixSlopeSign::HelixAngle
                               ? "f_Hβ > 0 when the actual helix angle is larger than designed"
                               : "f_Hβ > 0 when material increases away from the datum face";
  return "deviations " + dir + "; plus material positive; f_Hα > 0 when material increases towards the tip; " + sign;
}

double reported_per_normal(const IsoConventions& c) {
  if (c.direction == IsoDirection::Normal) return 1.0;
  const double cb = std::cos(c.base_helix_angle_rad);
  if (!std::isfinite(cb) || !(cb > 0.0))
    throw std::invalid_argument(fmt::format("base helix angle {} rad is not in (−π/2, π/2)", c.base_helix_angle_rad));
  return 1.0 / cb;
}

double helix_slope_factor(const IsoConventions& c, Flank side) {
  if (c.helix_slope_sign == HelixSlopeSign::RiseTowardsPlusZ) return 1.0;
  const double hand = c.base_helix_angle_rad < 0.0 ? -1.0 : 1.0; // spur counts as right hand [M]
  return hand * side_sign(side);
}

GearEvaluation evaluate_gear(const GearMeasurement& m, const GearParameters& p) {
  const int z = p.teeth;
  if (z < 1) throw std::invalid_argument(fmt::format("gear evaluation: {} teeth", z));
  GearEvaluation out;
  out.conventions = m.conventions;
  const double k_reported = reported_per_normal(m.conventions);
  Worst worst;

  // Flanks: traces.
  std::vector<char> seen(static_cast<std::size_t>(2 * z), 0);
  double sum_Ha[2] = {0, 0}, sum_Hb[2] = {0, 0};
  int count[2] = {0, 0};
  for (const auto& f : m.flanks) {
    check_tooth(f.tooth, z, "flank");
    auto& s = seen[slot(f.tooth, f.side)];
    if (s) throw std::invalid_argument(fmt::format("{} flank is given twice", flank_name(f.tooth, f.side)));
    s = 1;
    FlankEvaluation fe{f.tooth, f.side, {}, {}};
    try {
      fe.profile = evaluate_trace(f.profile);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("{} flank, profile: {}", flank_name(f.tooth, f.side), e.what()));
    }
    try {
      fe.helix = evaluate_trace(f.helix);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("{} flank, helix: {}", flank_name(f.tooth, f.side), e.what()));
    }
    scale(fe.profile, k_reported);
    scale(fe.helix, k_reported);
    fe.helix.slope_um *= helix_slope_factor(m.conventions, f.side);
    const int i = f.side == Flank::Right ? 1 : 0;
    sum_Ha[i] += fe.profile.slope_um;
    sum_Hb[i] += fe.helix.slope_um;
    ++count[i];
    const std::string where = flank_name(f.tooth, f.side);
    worst.add(Quantity::ProfileTotal, fe.profile.total_um, where);
    worst.add(Quantity::ProfileForm, fe.profile.form_um, where);
    worst.add(Quantity::ProfileSlope, fe.profile.slope_um, where);
    worst.add(Quantity::HelixTotal, fe.helix.total_um, where);
    worst.add(Quantity::HelixForm, fe.helix.form_um, where);
    worst.add(Quantity::HelixSlope, fe.helix.slope_um, where);
    out.flanks.push_back(std::move(fe));
  }
  for (int i = 0; i < 2; ++i) {
    SideMeans& sm = i == 1 ? out.right : out.left;
    sm.flanks = count[i];
    if (count[i] > 0) {
      sm.f_Halpha_m_um = sum_Ha[i] / count[i];
      sm.f_Hbeta_m_um = sum_Hb[i] / count[i];
    }
  }

  // Pitch points: pitch per side, runout.
  std::vector<std::optional<double>> dn(static_cast<std::size_t>(2 * z));
  for (const auto& pp : m.pitch_points) {
    check_tooth(pp.tooth, z, "pitch point");
    auto& v = dn[slot(pp.tooth, pp.side)];
    if (v) throw std::invalid_argument(fmt::format("pitch point of {} is given twice", flank_name(pp.tooth, pp.side)));
    v = pp.normal_deviation_um;
  }
  if (!m.pitch_points.empty() && !m.pitch_geometry)
    throw std::invalid_argument("pitch points were given without pitch_geometry");

  std::vector<double> side_values[2];
  bool complete[2] = {true, true};
  int measured[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    const Flank side = i == 1 ? Flank::Right : Flank::Left;
    for (int t = 1; t <= z; ++t) {
      const auto& v = dn[slot(t, side)];
      if (v) {
        side_values[i].push_back(*v);
        ++measured[i];
      } else {
        complete[i] = false;
      }
    }
    if (!complete[i] || z < 3) {
      out.notes.push_back(fmt::format("pitch deviations of the {} flanks not available: {} of {} teeth measured{}",
                                      to_string(side), measured[i], z, z < 3 ? " (at least 3 teeth needed)" : ""));
      continue;
    }
    auto pe = evaluate_pitch(side_values[i], side, *m.pitch_geometry, m.sector_pitches);
    const std::string where = fmt::format("{} flanks", to_string(side));
    worst.add(Quantity::SinglePitch, pe.f_p_um, where);
    worst.add(Quantity::CumulativePitch, pe.F_p_um, where);
    (i == 1 ? out.pitch_right : out.pitch_left) = std::move(pe);
  }
  if (complete[0] && complete[1] && z >= 3) {
    out.runout = evaluate_runout(side_values[1], side_values[0], *m.pitch_geometry);
    worst.add(Quantity::Runout, out.runout->F_r_um, "all tooth spaces");
  } else {
    out.notes.push_back(fmt::format("runout not available: needs both flanks of all {} teeth ({} right, {} left measured)",
                                    z, measured[1], measured[0]));
  }

  // Classification.
  Classification& c = out.classification;
  c.refusal = validity_refusal(p);
  if (!c.refusal) {
    for (auto& q : worst.list) {
      q.flank_class = tolerance_class(q.quantity, q.worst_value_um, p);
      if (!c.overall || *q.flank_class > *c.overall) {
        c.overall = q.flank_class;
        c.governing = q.quantity;
      }
    }
  }
  c.quantities = std::move(worst.list); // worst values are reported even when classification is refused
  return out;
}

} // namespace geartopo::evaluation
