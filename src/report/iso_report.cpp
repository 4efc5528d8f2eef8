#include "geartopo/report/iso_report.hpp"

#include "geartopo/evaluation/tolerances.hpp"
#include "geartopo/gears/involute.hpp"

#include <fmt/format.h>

#include <cmath>
#include <algorithm>
#include <map>
#include <numbers>

namespace geartopo::report {
namespace {

using evaluation::Quantity;

nlohmann::json class_json(Quantity q, double value, const evaluation::GearParameters& p, bool refused) {
  if (refused) return nullptr;
  return evaluation::class_label(evaluation::tolerance_class(q, value, p));
}

nlohmann::json opt(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }

} // namespace

nlohmann::json class5_tolerances_json(const evaluation::GearParameters& p) {
  if (evaluation::validity_refusal(p)) return nullptr;
  nlohmann::json t;
  const std::pair<Quantity, const char*> keys[] = {
      {Quantity::SinglePitch, "f_pT_um"},   {Quantity::CumulativePitch, "F_pT_um"}, {Quantity::ProfileSlope, "f_HalphaT_um"},
      {Quantity::ProfileForm, "f_falphaT_um"}, {Quantity::ProfileTotal, "F_alphaT_um"}, {Quantity::HelixSlope, "f_HbetaT_um"},
      {Quantity::HelixForm, "f_fbetaT_um"}, {Quantity::HelixTotal, "F_betaT_um"},    {Quantity::Runout, "F_rT_um"}};
  for (const auto& [q, key] : keys) t[key] = evaluation::tolerance_um(q, p, 5);
  return t;
}

nlohmann::json iso_json(const IsoResult& res) {
  const auto& e = res.evaluation;
  const auto& p = res.parameters;
  const bool refused = e.classification.refusal.has_value();
  nlohmann::json j;
  j["iso_direction"] = std::string(evaluation::to_string(e.conventions.direction));
  j["helix_slope_sign"] = std::string(evaluation::to_string(e.conventions.helix_slope_sign));
  j["conventions"] = evaluation::describe(e.conventions);

  // Per-flank pitch values: f_p of the pitch that starts at this flank, its index deviation, and the runout of the
  // space that follows it (right flank) or precedes it (left flank).
  std::map<std::pair<int, int>, std::pair<double, double>> pitch_of;
  for (const auto* pe : {&e.pitch_left, &e.pitch_right})
    if (*pe)
      for (size_t i = 0; i < (*pe)->single_pitch_um.size(); ++i)
        pitch_of[{static_cast<int>(i + 1), static_cast<int>((*pe)->side)}] = {(*pe)->single_pitch_um[i], (*pe)->index_um[i]};

  nlohmann::json flanks = nlohmann::json::array();
  for (const auto& f : e.flanks) {
    nlohmann::json fj;
    fj["tooth"] = f.tooth;
    fj["flank"] = evaluation::to_string(f.side);
    fj["F_alpha_um"] = f.profile.total_um;
    fj["f_falpha_um"] = f.profile.form_um;
    fj["f_Halpha_um"] = f.profile.slope_um;
    fj["F_beta_um"] = f.helix.total_um;
    fj["f_fbeta_um"] = f.helix.form_um;
    fj["f_Hbeta_um"] = f.helix.slope_um;
    nlohmann::json classes;
    classes["F_alpha"] = class_json(Quantity::ProfileTotal, f.profile.total_um, p, refused);
    classes["f_falpha"] = class_json(Quantity::ProfileForm, f.profile.form_um, p, refused);
    classes["f_Halpha"] = class_json(Quantity::ProfileSlope, f.profile.slope_um, p, refused);
    classes["F_beta"] = class_json(Quantity::HelixTotal, f.helix.total_um, p, refused);
    classes["f_fbeta"] = class_json(Quantity::HelixForm, f.helix.form_um, p, refused);
    classes["f_Hbeta"] = class_json(Quantity::HelixSlope, f.helix.slope_um, p, refused);
    // Per flank: the individual pitch deviations of this flank (ISO 1328-1 f_pi, F_pi: the gear's f_p and F_p are the
    // worst of them, under "gear") and the ball's radial position in the space after it (the gear's F_r is their range).
    const auto it = pitch_of.find({f.tooth, static_cast<int>(f.side)});
    if (it != pitch_of.end()) {
      fj["f_pi_um"] = it->second.first;
      fj["F_pi_um"] = it->second.second;
      classes["f_p"] = class_json(Quantity::SinglePitch, it->second.first, p, refused);
    } else {
      fj["f_pi_um"] = nullptr;
      fj["F_pi_um"] = nullptr;
    }
    if (e.runout) {
      const int s = f.side == geartopo::Flank::Right ? f.tooth : (f.tooth == 1 ? p.teeth : f.tooth - 1);
      fj["radial_position_um"] = e.runout->radial_um[static_cast<size_t>(s - 1)]; // of the ball in that space; may be < 0
    } else {
      fj["radial_position_um"] = nullptr;
    }
    fj["classes"] = classes;
    // Flank twist of the deviation from the design (docs/modifications.md): null without a grid (measured traces).
    const auto tw = std::find_if(res.twists.begin(), res.twists.end(),
                                 [&](const auto& t) { return t.tooth == f.tooth && t.flank == f.side; });
    fj["S_alpha_um"] = tw != res.twists.end() ? nlohmann::json(tw->twist.profile_twist_um) : nlohmann::json(nullptr);
    fj["S_beta_um"] = tw != res.twists.end() ? nlohmann::json(tw->twist.helix_twist_um) : nlohmann::json(nullptr);
    flanks.push_back(fj);
  }
  j["flanks"] = flanks;

  nlohmann::json gear;
  for (const auto* pe : {&e.pitch_left, &e.pitch_right}) {
    const char* side = pe == &e.pitch_left ? "left" : "right";
    if (*pe)
      gear["pitch"][side] = {{"f_p_um", (*pe)->f_p_um}, {"F_p_um", (*pe)->F_p_um}, {"F_pk_um", (*pe)->F_pk_um},
                             {"k", (*pe)->sector_pitches}};
    else
      gear["pitch"][side] = nullptr;
  }
  gear["F_r_um"] = e.runout ? nlohmann::json(e.runout->F_r_um) : nlohmann::json(nullptr);
  gear["f_Halpha_m_um"] = {{"left", opt(e.left.f_Halpha_m_um)}, {"right", opt(e.right.f_Halpha_m_um)}};
  gear["f_Hbeta_m_um"] = {{"left", opt(e.left.f_Hbeta_m_um)}, {"right", opt(e.right.f_Hbeta_m_um)}};
  j["gear"] = gear;
  j["notes"] = e.notes;

  nlohmann::json cls;
  cls["refusal"] = refused ? nlohmann::json(*e.classification.refusal) : nlohmann::json(nullptr);
  cls["overall"] = e.classification.overall ? nlohmann::json(evaluation::class_label(*e.classification.overall)) : nlohmann::json(nullptr);
  cls["governing"] = e.classification.governing ? nlohmann::json(std::string(evaluation::symbol(*e.classification.governing)))
                                                : nlohmann::json(nullptr);
  nlohmann::json qs = nlohmann::json::array();
  for (const auto& q : e.classification.quantities)
    qs.push_back({{"quantity", std::string(evaluation::symbol(q.quantity))},
                  {"worst_um", q.worst_value_um},
                  {"where", q.where},
                  {"class", q.flank_class ? nlohmann::json(evaluation::class_label(*q.flank_class)) : nlohmann::json(nullptr)}});
  cls["quantities"] = qs;
  j["classification"] = cls;
  j["tolerances_class5_um"] = class5_tolerances_json(p);
  return j;
}

std::string iso_table(const IsoResult& res) {
  const auto& e = res.evaluation;
  std::string out = fmt::format("ISO 1328-1:2013 — deviations in µm, {} direction, class of each value\n  ({})\n",
                                evaluation::to_string(e.conventions.direction), evaluation::describe(e.conventions));
  // Each value with its class beside it ("–" when ISO 1328-1 does not apply to the gear).
  const bool refused = e.classification.refusal.has_value();
  const auto cell = [&](Quantity q, double v) {
    const std::string cls = refused ? "–" : evaluation::class_label(evaluation::tolerance_class(q, v, res.parameters));
    return fmt::format("{:>8.2f} {:>3}", v, cls == "worse than 11" ? ">11" : cls);
  };
  out += fmt::format("  {:>5} {:<5} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}\n", "tooth", "flank", "F_α cl", "f_fα cl",
                     "f_Hα cl", "F_β cl", "f_fβ cl", "f_Hβ cl");
  for (const auto& f : e.flanks)
    out += fmt::format("  {:>5} {:<5} {} {} {} {} {} {}\n", f.tooth, evaluation::to_string(f.side),
                       cell(Quantity::ProfileTotal, f.profile.total_um), cell(Quantity::ProfileForm, f.profile.form_um),
                       cell(Quantity::ProfileSlope, f.profile.slope_um), cell(Quantity::HelixTotal, f.helix.total_um),
                       cell(Quantity::HelixForm, f.helix.form_um), cell(Quantity::HelixSlope, f.helix.slope_um));
  for (const auto* pe : {&e.pitch_left, &e.pitch_right})
    if (*pe)
      out += fmt::format("  pitch, {} flanks: f_p {:.2f}  F_p {:.2f}  F_pk(k={}) {:.2f}\n", evaluation::to_string((*pe)->side),
                         (*pe)->f_p_um, (*pe)->F_p_um, (*pe)->sector_pitches, (*pe)->F_pk_um);
  if (e.runout) out += fmt::format("  runout F_r {:.2f}\n", e.runout->F_r_um);
  for (const auto& n : e.notes) out += "  note: " + n + "\n";
  const auto& c = e.classification;
  if (c.refusal) {
    out += "  classification refused: " + *c.refusal + "\n";
    return out;
  }
  out += "  worst values and classes:\n";
  for (const auto& q : c.quantities)
    out += fmt::format("    {:<5} {:>8.2f}  class {:<13} ({})\n", evaluation::symbol(q.quantity), q.worst_value_um,
                       evaluation::class_label(q.flank_class), q.where);
  if (c.overall)
    out += fmt::format("  overall flank tolerance class: {} (set by {})\n", evaluation::class_label(*c.overall),
                       c.governing ? std::string(evaluation::symbol(*c.governing)) : "-");
  // Twist of the deviation from the design over each flank's grid (docs/modifications.md); none for measured traces.
  if (!res.twists.empty()) {
    const auto largest = [&](auto member) {
      return *std::max_element(res.twists.begin(), res.twists.end(), [&](const auto& a, const auto& b) {
        return std::abs(a.twist.*member) < std::abs(b.twist.*member);
      });
    };
    const auto sa = largest(&evaluation::FlankTwist::profile_twist_um), sb = largest(&evaluation::FlankTwist::helix_twist_um);
    out += fmt::format("  flank twist (grid, from the design): largest S_α {:+.2f} µm (tooth {} {}), largest S_β {:+.2f} µm "
                       "(tooth {} {})\n",
                       sa.twist.profile_twist_um, sa.tooth, gears::to_string(sa.flank), sb.twist.helix_twist_um, sb.tooth,
                       gears::to_string(sb.flank));
  }
  return out;
}

} // namespace geartopo::report
