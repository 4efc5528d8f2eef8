// Diagnosis on measurements whose hidden effects are computed WITHOUT the effect plug-ins (issue 14): each hidden
// deviation is written here from the documented conventions (docs/diagnosis.md, docs/adding-an-effect.md) and the
// wheel path's time stamps, so a wrong physics in src/effects/ or a false culprit shows up as a failed case.
//
// What is shared with the code under test, and why that is fair: the default scene's model (the simulator's exact
// deviation of the scene as it is, without the hidden effect), the nominal flank (its point and normal) and the ideal
// machine chain (Eq. 11: where the wheel is for commanded axes). What is NOT shared: how an effect becomes a deviation.
// Here an axis offset δq at time t moves the wheel rigidly, P' = wMg(q + δq)·wMg(q)⁻¹·P, and the material left at a
// flank point changes by (P' − P)·n (n out of the material: a wheel moved away leaves more); a wheel worn by w along
// its normal leaves +w; a gear mounted off-centre by e on the table sees the wheel displaced by −e. The time and the
// stroke of a point are those of its generating pose (the wheel path's time stamp there).
//
// Units: µm (deviations, noise), mm (positions), s, rad. Scored over the whole set (targets of issue 14): ≥ 90 % of
// cases right, zero false culprits, parameters within 2σ in ≥ 90 %, residual after adding ≤ 1.5× noise where the truth
// is in the library. Ambiguous verdicts are followed literally (the plan's teeth and grid, synthesised here from the
// same truth with a new seed). Run time: 11 cases × 2 seeds, each one `diagnose` on 252 points (63 on one flank), plus
// the follow-ups (≈ 60 s wall in Release on the shared machine).
#include "geartopo/diagnosis/diagnosis_json.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/report/measurement_report.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <iostream>
#include <sstream>

using namespace geartopo;

#include "independent_truth.hpp"

namespace independent_truth {

// ---- hidden effects, each as a formula of the contact (µm) ----

/// Thermal growth of X and Z towards a steady state, δ(t) = δ∞ (1 − e^(−t/τ)) (docs/diagnosis.md: X growth leaves
/// the wheel further out).
std::function<double(const Contact&)> thermal(double x_um, double z_um, double tau_s) {
  return [=](const Contact& c) {
    const double f = 1.0 - std::exp(-c.pp.time_s / tau_s);
    machine::AxisPose dq;
    dq.x = 1e-3 * x_um * f;
    dq.z = 1e-3 * z_um * f;
    return axis_offset_um(c, dq);
  };
}

/// Even wheel wear w per stroke along the wheel's normal: a smaller wheel leaves w·(strokes so far) more material.
std::function<double(const Contact&)> wear(double um_per_stroke) {
  return [=](const Contact& c) { return um_per_stroke * c.strokes_before; };
}

/// Gear mounted off the table's axis by e = (e_x, e_y) (gear frame): the wheel, positioned from the table axis, sits
/// at −e relative to the gear.
std::function<double(const Contact&)> eccentric(double ex_um, double ey_um) {
  return [=](const Contact& c) { return -(ex_um * c.fp.n.x() + ey_um * c.fp.n.y()); };
}

/// OUTSIDE the library: the swivel axis A drifting by a fixed angle per stroke (a loose clamping of the head).
std::function<double(const Contact&)> swivel_drift(double urad_per_stroke) {
  return [=](const Contact& c) {
    machine::AxisPose dq;
    dq.a = 1e-6 * urad_per_stroke * c.strokes_before;
    return axis_offset_um(c, dq);
  };
}

/// OUTSIDE the library: wear concentrated at the wheel's outer edge, which grinds the root end of the profile: w per
/// stroke at the root end of the measured profile, fading exponentially over a fifth of it.
std::function<double(const Contact&)> edge_wear(double um_per_stroke) {
  return [=](const Contact& c) { return um_per_stroke * c.strokes_before * std::exp(-c.profile_fraction / 0.2); };
}

/// The workpiece arbor bending away from the wheel under the grinding force (docs/diagnosis.md): a point load at the
/// contact's place s on a simply supported arbor of span L, the gear in its middle, δ(s) = δ_mid·16 s²(L − s)²/L⁴; the
/// wheel's stroke Z is the contact's place along the face width b. The workpiece giving way leaves material as a
/// wheel moved out in X would.
std::function<double(const Contact&)> arbor_deflection(double mid_um, double span_mm, double face_width_mm) {
  return [=](const Contact& c) {
    const double s = 0.5 * (span_mm - face_width_mm) + std::clamp(c.pp.z_stroke_mm, 0.0, face_width_mm);
    machine::AxisPose dq;
    dq.x = 1e-3 * mid_um * 16.0 * s * s * (span_mm - s) * (span_mm - s) / std::pow(span_mm, 4);
    return axis_offset_um(c, dq);
  };
}

// ---- the cases ----

struct Truth {
  std::string name;
  std::vector<std::string> effects; ///< library effects hidden (sorted); empty: none of the library
  bool in_library = true;           ///< false: the hidden effect is outside the library ("unexplained" expected)
  std::function<double(const Contact&)> hidden; ///< µm at a contact; null: none
  std::map<std::string, double> parameters;      ///< "effect.key" → true value, those to recover within 2σ
  double thickness_um = 0.0, rotation_urad = 0.0; ///< set-up terms added
  double noise_um = 0.5;
  bool expect_ambiguous = false; ///< the two teeth cannot tell the truth from another explanation (issue 14)
  bool on_one_flank = false;     ///< measured on one_flank(), else two_teeth(); naming nothing is then honest too
  /// Outside the library: the machine elements (diagnosis' hypotheses beyond the library, "E_AOA linear_in_time") that
  /// are this truth; naming one of them, or "unexplained", is right.
  std::vector<std::string> elements = {};
  const Layout& layout() const { return on_one_flank ? one_flank() : two_teeth(); }
};

/// The outcome of one case, scored against its truth.
struct Score {
  bool right = false, false_culprit = false, ambiguous = false;
  int parameters_checked = 0, parameters_within = 0;
  bool residual_checked = false, residual_ok = false;
  std::string report;
};

std::vector<measurement::MeasuredPoint> measure(const Layout& l, const Truth& t, std::uint64_t seed,
                                                const workbench::Workbench& b = bench()) {
  const auto& g = b.setup.geometry();
  const double um_per_urad = 0.5 * g.base_diameter_mm() * std::cos(g.base_helix_angle()) * 1e-3; // r_b cos β_b
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, t.noise_um);
  auto pts = l.points;
  for (size_t i = 0; i < pts.size(); ++i) {
    auto& p = pts[i];
    if (t.hidden) p.deviation_um += t.hidden(l.contacts[i]);
    p.deviation_um += t.thickness_um + (p.flank == Flank::Right ? 1.0 : -1.0) * um_per_urad * t.rotation_urad;
    p.deviation_um += noise(rng);
  }
  return pts;
}

std::vector<std::string> sorted_types(const diagnosis::Candidate& c) {
  std::vector<std::string> v;
  for (const auto& e : c.effects) v.push_back(e.type);
  std::sort(v.begin(), v.end());
  return v;
}

/// A fitted parameter at the end of its allowed range (the effect's declared bounds: metadata, not its physics).
bool on_a_bound(const diagnosis::Candidate& c) {
  for (size_t e = 0; e < c.effects.size(); ++e) {
    const auto specs = effects::make_effect(c.effects[e].type)->parameters();
    for (size_t k = 0; k < specs.size(); ++k) {
      const double v = c.effects[e].values[k], end = 1e-6 * (specs[k].hi - specs[k].lo);
      if (specs[k].fitted && (v <= specs[k].lo + end || v >= specs[k].hi - end)) return true;
    }
  }
  return false;
}

Score score(const Truth& t, const diagnosis::Diagnosis& d) {
  Score s;
  std::ostringstream why;
  why << t.name << ": ";
  s.ambiguous = !d.rivals.empty();
  // The explanations the verdict names: the chosen one, and its rivals when it says "ambiguous".
  std::vector<const diagnosis::Candidate*> named;
  if (d.chosen) named.push_back(&*d.chosen);
  for (const auto& r : d.rivals) named.push_back(&r);
  const diagnosis::Candidate* truth_named = nullptr;
  bool foreign = false; // a named explanation holds an effect that is not hidden
  for (const auto* c : named) {
    if (sorted_types(*c) == t.effects) truth_named = c;
    // A machine element beyond the library (a component change, one wheel flank's profile, the wheel profile's
    // wear) named for a library truth is a wrong explanation too, unless it says that the truth's effect leaves the
    // same field on these flanks (its library_equivalent).
    const bool machine_element = c->family != nullptr;
    if (machine_element) {
      const bool says_truth = t.effects.size() == 1 && std::find(c->library_equivalent.begin(), c->library_equivalent.end(),
                                                                  t.effects.front()) != c->library_equivalent.end();
      foreign |= !t.effects.empty() && !says_truth;
    } else {
      for (const auto& n : sorted_types(*c))
        foreign |= std::find(t.effects.begin(), t.effects.end(), n) == t.effects.end();
    }
    why << (c == named.front() ? "chose " : " | rival ") << c->name();
  }
  if (named.empty()) why << "chose nothing";
  if (!t.in_library) {
    // Outside the library: a library effect named is a false culprit; right is "unexplained" or the machine element
    // that is the truth (named, or in the named one's equivalence class).
    const auto is_truth = [&](const std::string& n) {
      return std::find(t.elements.begin(), t.elements.end(), n) != t.elements.end();
    };
    bool element_named = false;
    if (d.chosen && d.beyond_library) {
      element_named = is_truth(d.chosen->name());
      for (const auto& e : d.chosen->equivalent) element_named = element_named || is_truth(e);
      why << " [" << d.chosen->description << "; equivalent: " << d.chosen->equivalent.size() << "]";
    }
    s.false_culprit = d.chosen.has_value() && !element_named;
    s.right = !s.false_culprit && (d.unexplained || element_named);
  } else if (t.effects.empty()) {
    s.false_culprit = d.chosen.has_value();
    s.right = !d.chosen;
  } else {
    // With one measured flank, naming nothing (the data cannot say) is honest; naming a wrong one alone never is. A
    // machine element named with the truth as its library equivalent (the same field on these flanks: an X drifting
    // linearly ≡ a thermal X growth in its early phase) names the truth's physics.
    bool truth_equivalent = false;
    if (d.chosen && t.effects.size() == 1)
      for (const auto& e : d.chosen->library_equivalent) truth_equivalent |= e == t.effects.front();
    if (truth_equivalent) why << " [library equivalent: " << t.effects.front() << "]";
    s.right = truth_named != nullptr || truth_equivalent || (t.on_one_flank && !d.chosen);
    // Ambiguous between the truth and something else is no false culprit; naming only wrong explanations is.
    s.false_culprit = foreign && truth_named == nullptr && !truth_equivalent;
  }
  // A value on its box is no measurement (issue 27, item 4): printed or written as a finding it makes the verdict
  // wrong; withheld from the scene, with the combinations the data do fix printed instead, it is the honest report of a
  // parameter these teeth cannot determine.
  if (d.chosen && on_a_bound(*d.chosen) && (!d.withheld || d.determined.empty()))
    s.false_culprit = true, s.right = false;
  // Parameters: every hidden parameter, on the named explanation that holds exactly the hidden effects, within 2σ.
  if (truth_named)
    for (size_t e = 0; e < truth_named->effects.size(); ++e)
      for (const auto& p : truth_named->parameters[e]) {
        const auto it = t.parameters.find(truth_named->effects[e].type + "." + p.key);
        if (it == t.parameters.end()) continue;
        ++s.parameters_checked;
        const bool within = std::abs(p.value - it->second) <= 2.0 * p.uncertainty;
        s.parameters_within += within;
        why << "; " << it->first << " " << p.value << " ± " << p.uncertainty << " (truth " << it->second << ")";
      }
  if (t.effects.empty() && t.in_library) { // the set-up terms are the parameters of these cases
    s.parameters_checked += 2;
    s.parameters_within += std::abs(d.setup.thickness_um - t.thickness_um) <= 2.0 * d.setup.thickness_sd_um;
    s.parameters_within += std::abs(d.setup.rotation_urad - t.rotation_urad) <= 2.0 * d.setup.rotation_sd_urad;
    why << "; thickness " << d.setup.thickness_um << " ± " << d.setup.thickness_sd_um << " (truth " << t.thickness_um
        << "), rotation " << d.setup.rotation_urad << " ± " << d.setup.rotation_sd_urad << " (truth " << t.rotation_urad << ")";
  }
  if (truth_named) {
    s.residual_checked = true;
    s.residual_ok = truth_named->rms_after_um <= 1.5 * t.noise_um;
    why << "; rms after " << truth_named->rms_after_um;
  }
  why << "\n    verdict: " << d.verdict;
  s.report = why.str();
  return s;
}

diagnosis::Diagnosis run(const std::vector<measurement::MeasuredPoint>& pts, double noise_um,
                         const workbench::Workbench& b = bench()) {
  diagnosis::DiagnoseOptions o;
  o.noise_um = noise_um;
  return diagnosis::diagnose(b.setup, b.process(), pts, {}, o);
}

std::vector<Truth> library_set() {
  return {
      {"noise only", {}, true, nullptr, {}},
      {"uniform thickness offset +3 um", {}, true, nullptr, {}, 3.0, 0.0},
      {"rigid rotation 20 urad", {}, true, nullptr, {}, 0.0, 20.0},
      {"thermal drift X 9 um, Z 4 um, tau 600 s", {"thermal_drift"}, true, thermal(9.0, 4.0, 600.0),
       {{"thermal_drift.x_growth_um", 9.0}, {"thermal_drift.z_growth_um", 4.0}, {"thermal_drift.time_constant_s", 600.0}}},
      {"wheel wear 0.25 um/stroke", {"wheel_wear"}, true, wear(0.25), {{"wheel_wear.wear_um_per_stroke", 0.25}}},
      {"eccentricity (6, -4) um", {"eccentricity"}, true, eccentric(6.0, -4.0),
       {{"eccentricity.ecc_x_um", 6.0}, {"eccentricity.ecc_y_um", -4.0}}},
      {"wear 0.25 um/stroke + eccentricity (6, -4) um", {"eccentricity", "wheel_wear"}, true,
       [w = wear(0.25), e = eccentric(6.0, -4.0)](const Contact& c) { return w(c) + e(c); },
       {{"wheel_wear.wear_um_per_stroke", 0.25}, {"eccentricity.ecc_x_um", 6.0}, {"eccentricity.ecc_y_um", -4.0}}},
      {"thermal drift X 9 um, tau 600 s at 1.5 um noise", {"thermal_drift"}, true, thermal(9.0, 0.0, 600.0),
       {{"thermal_drift.x_growth_um", 9.0}}, 0.0, 0.0, 1.5, true},
      {"swivel drift 20 urad/stroke (outside the library)", {}, false, swivel_drift(20.0), {}, 0.0, 0.0, 0.5, false, false,
       {"E_AOA linear_in_time", "epsilon_xa linear_in_time"}},
      {"edge wear 0.4 um/stroke (outside the library)", {}, false, edge_wear(0.4), {}, 0.0, 0.0, 0.5, false, false,
       {"wheel_profile_wear"}},
      {"thermal drift X 9 um, Z 4 um, tau 600 s on one measured flank", {"thermal_drift"}, true,
       thermal(9.0, 4.0, 600.0),
       {{"thermal_drift.x_growth_um", 9.0}, {"thermal_drift.z_growth_um", 4.0}, {"thermal_drift.time_constant_s", 600.0}},
       0.0, 0.0, 0.5, false, true},
  };
}

/// The measured points and the plan's recommendation followed literally: its new teeth on its grid, synthesised from
/// the same truth with a new noise seed, added to the points already measured.
std::vector<measurement::MeasuredPoint> follow(const std::vector<measurement::MeasuredPoint>& measured, const Truth& t,
                                               const diagnosis::MeasurementOption& m, std::uint64_t seed) {
  auto pts = measured;
  const auto more = measure(make_layout(m.teeth, m.rows, m.cols), t, seed);
  pts.insert(pts.end(), more.begin(), more.end());
  return pts;
}

/// Decided (issue 14): the truth is the chosen explanation, and either no rival is left within the ΔBIC threshold or
/// the plan's competitor (`competitor`, Candidate::name()) now trails it by more than the threshold (10). `why` says
/// which, and names a new rival when one appeared.
bool decided_for_truth(const Truth& t, const diagnosis::Diagnosis& d, const std::string& competitor, std::string* why) {
  // The truth's physics named: the truth itself, or (as score counts it right) a machine element that says the truth
  // leaves the same field on these flanks — an X drifting linearly for a thermal X growth in its early phase.
  const bool says_truth = d.chosen && d.beyond_library && t.effects.size() == 1 &&
                          std::find(d.chosen->library_equivalent.begin(), d.chosen->library_equivalent.end(),
                                    t.effects.front()) != d.chosen->library_equivalent.end();
  if (!d.chosen || (sorted_types(*d.chosen) != t.effects && !says_truth)) return false;
  if (d.rivals.empty()) return *why = "no rival left", true;
  double competitor_bic = 1e300;
  for (const auto& c : d.ranked)
    if (c.name() == competitor) competitor_bic = c.delta_bic;
  for (const auto& c : d.rivals)
    if (c.name() == competitor) competitor_bic = c.delta_bic;
  const double gap = competitor_bic - d.chosen->delta_bic;
  *why = competitor + " trails by " + std::to_string(gap) + " in ΔBIC; new rival " + d.rivals.front().name() +
         " trails by " + std::to_string(d.rivals.front().delta_bic - d.chosen->delta_bic);
  return gap > 10.0;
}

/// The plan's other explanation than the truth.
std::string competitor_of(const Truth& t, const diagnosis::MeasurementPlan& plan) {
  std::string truth;
  for (const auto& e : t.effects) truth += (truth.empty() ? "" : " + ") + e;
  // Candidate::name() keeps the fit's order, the truth is sorted: compare as sorted sets of names.
  const auto sorted = [](std::string name) {
    std::vector<std::string> parts;
    for (size_t at; (at = name.find(" + ")) != std::string::npos; name.erase(0, at + 3)) parts.push_back(name.substr(0, at));
    parts.push_back(name);
    std::sort(parts.begin(), parts.end());
    return parts;
  };
  return sorted(plan.first) == t.effects ? plan.second : plan.first;
}

std::string option_text(const diagnosis::MeasurementOption& m) {
  std::ostringstream o;
  o << "teeth";
  for (int tooth : m.teeth) o << " " << tooth;
  o << " on " << m.rows << " x " << m.cols << " (" << m.points << " points; expected gap " << m.delta_bic_if_first
    << " / " << m.delta_bic_if_second << ", raw " << m.separation_before_refit_sigma << " sigma"
    << (m.resolves ? "" : ", NOT expected to resolve") << ")";
  return o.str();
}

/// Outside the library the three outputs must agree (issue 14): the verdict says "Unexplained", names the nearest
/// library explanation and why it was rejected, never "Missing"; diagnosis.json (what the report writes) has no chosen
/// effect, unexplained true, the same nearest with the same reason, and the same verdict.
void expect_unexplained_reported_alike(const diagnosis::Diagnosis& d, const std::string& name) {
  EXPECT_EQ(d.verdict.rfind("Set-up", 0), 0u) << name << ": " << d.verdict;
  EXPECT_NE(d.verdict.find("Unexplained: no effect of the library"), std::string::npos) << name << ": " << d.verdict;
  EXPECT_EQ(d.verdict.find("Missing"), std::string::npos) << name << ": " << d.verdict;
  EXPECT_NE(d.verdict.find("What is left unexplained: "), std::string::npos) << name << ": " << d.verdict;
  ASSERT_TRUE(d.residual_pattern) << name;
  ASSERT_TRUE(d.nearest_rejection) << name;
  ASSERT_TRUE(d.nearest.has_value()) << name << ": " << d.verdict;
  EXPECT_NE(d.verdict.find("Nearest library explanation: " + d.nearest->name()), std::string::npos) << d.verdict;
  EXPECT_NE(d.verdict.find("rejected: " + diagnosis::to_text(*d.nearest_rejection)), std::string::npos) << d.verdict;
  const auto j = diagnosis::diagnosis_json("scene.yaml", "measured.csv", d, 0.0);
  EXPECT_TRUE(j["chosen"].is_null()) << name;
  EXPECT_TRUE(j["unexplained"].get<bool>()) << name;
  EXPECT_FALSE(j["ambiguous"].get<bool>()) << name;
  EXPECT_EQ(j["nearest"]["effect"], d.nearest->name()) << name;
  EXPECT_EQ(j["nearest"]["rejected_because"], diagnosis::to_text(*d.nearest_rejection)) << name;
  EXPECT_EQ(j["residual_pattern"], diagnosis::to_text(*d.residual_pattern)) << name;
  EXPECT_EQ(j["verdict"], d.verdict) << name;
  // The χ² of the "more than noise" test, recomputed here from what is left (no stroke scatter declared: the residual
  // shown is the one tested) and the noise.
  double chi2 = 0.0;
  for (double r : d.residual_after_um) chi2 += (r / d.noise_um) * (r / d.noise_um);
  EXPECT_NEAR(j["residual_chi2"].get<double>(), chi2, 1e-9 * chi2) << name;
  EXPECT_GT(j["residual_chi2_dof"].get<double>(), 0.0) << name;
  EXPECT_LT(j["residual_chi2_dof"].get<double>(), static_cast<double>(d.residual_after_um.size())) << name;
  for (const auto& c : j["candidates"]) EXPECT_FALSE(c["significant"].get<bool>()) << name << ": " << c["effect"];
}

} // namespace independent_truth

using namespace independent_truth;

// The whole set, two seeds per case, scored together against the targets of issue 14. Every ambiguous verdict on a
// library truth is followed literally — the recommended teeth on the recommended grid, synthesised from the same truth
// with a new seed, added to what was measured — and must then name the truth alone.
TEST(HiddenEffectsIndependent, DiagnosisMeetsTheTargetsOverTheSet) {
  int cases = 0, right = 0, false_culprits = 0, params = 0, params_within = 0, residuals = 0, residuals_ok = 0;
  int followed = 0, resolved = 0;
  std::string reports;
  std::uint64_t case_seed = 100;
  for (const auto& t : library_set())
    for (std::uint64_t seed : {++case_seed, case_seed + 1000}) { // each case its own noise
      const auto pts = measure(t.layout(), t, seed);
      double hidden_ss = 0.0;
      for (const auto& c : t.layout().contacts) hidden_ss += t.hidden ? std::pow(t.hidden(c), 2) : 0.0;
      const auto d = run(pts, t.noise_um);
      const Score s = score(t, d);
      ++cases;
      right += s.right;
      false_culprits += s.false_culprit;
      params += s.parameters_checked;
      params_within += s.parameters_within;
      residuals += s.residual_checked;
      residuals_ok += s.residual_ok;
      reports += std::string(s.right ? "  ok    " : "  WRONG ") + s.report +
                 "\n    hidden RMS " + std::to_string(std::sqrt(hidden_ss / static_cast<double>(pts.size()))) + " um\n";
      if (t.expect_ambiguous) {
        EXPECT_TRUE(s.ambiguous) << s.report;
      }
      if (!t.in_library && d.unexplained) expect_unexplained_reported_alike(d, t.name);
      if (!(s.ambiguous && t.in_library && d.plan && !d.plan->recommended.teeth.empty())) continue;
      ++followed;
      const auto after = run(follow(pts, t, d.plan->recommended, seed + 1), t.noise_um);
      const Score sa = score(t, after);
      std::string why;
      // What the named explanation leaves within 1.5× noise: the truth's own fit, or the element that says it.
      const bool residual_ok = sa.residual_checked ? sa.residual_ok
                                                   : after.chosen && after.chosen->rms_after_um <= 1.5 * t.noise_um;
      const bool ok = decided_for_truth(t, after, competitor_of(t, *d.plan), &why) && !sa.false_culprit && residual_ok;
      resolved += ok;
      reports += std::string(ok ? "    resolved by " : "    NOT resolved by ") + option_text(d.plan->recommended) +
                 " (" + why + "): " + sa.report + "\n";
    }
  std::cout << reports;
  std::cout << "tally: " << right << " of " << cases << " right, " << false_culprits << " false culprits, "
            << params_within << " of " << params << " parameters within 2 sigma, " << residuals_ok << " of "
            << residuals << " residuals within 1.5x noise, " << resolved << " of " << followed
            << " ambiguous verdicts resolved by following the plan\n";
  EXPECT_EQ(false_culprits, 0) << reports;
  EXPECT_GE(right, 0.9 * cases) << right << " of " << cases << " right\n" << reports;
  EXPECT_GE(params_within, 0.9 * params) << params_within << " of " << params << " parameters within 2σ\n" << reports;
  EXPECT_EQ(residuals_ok, residuals) << residuals_ok << " of " << residuals << " residuals within 1.5× noise\n" << reports;
  EXPECT_EQ(resolved, followed) << "ambiguous verdicts resolved by the recommended measurement\n" << reports;
}

// Issue 14's own case: thermal drift (X 9 µm, τ 600 s) at 1.5 µm noise on teeth 1 and 18 cannot be told from wheel
// wear. The verdict must say "ambiguous", and its plan — scored after refit — must expect to resolve it; followed
// literally (its teeth, its grid, a new noise seed) the diagnosis names thermal drift alone (truth: the formula above,
// not the plug-in). Seeds other than the set's.
TEST(HiddenEffectsIndependent, ThermalDriftVersusWearIsAmbiguousAndTheFollowedPlanResolvesIt) {
  const Truth t{"thermal drift X 9 um, tau 600 s at 1.5 um noise", {"thermal_drift"}, true, thermal(9.0, 0.0, 600.0),
                {{"thermal_drift.x_growth_um", 9.0}}, 0.0, 0.0, 1.5, true};
  for (std::uint64_t seed : {31u, 32u}) {
    const auto pts = measure(two_teeth(), t, seed);
    const auto d = run(pts, t.noise_um);
    const Score s = score(t, d);
    ASSERT_TRUE(s.ambiguous && s.right) << s.report;
    ASSERT_TRUE(d.plan.has_value());
    const auto& m = d.plan->recommended;
    EXPECT_TRUE(m.resolves) << option_text(m);
    EXPECT_GE(std::min(m.delta_bic_if_first, m.delta_bic_if_second), diagnosis::DiagnoseOptions{}.plan_target_delta_bic);
    // The verdict prints what is followed: the teeth and the grid.
    std::ostringstream printed;
    printed << "measure teeth ";
    for (size_t k = 0; k < m.teeth.size(); ++k) printed << (k ? "," : "") << m.teeth[k];
    printed << " with a " << m.rows << " × " << m.cols << " grid per flank";
    EXPECT_NE(d.verdict.find(printed.str()), std::string::npos) << printed.str() << "\n" << d.verdict;
    const auto after = run(follow(pts, t, m, seed + 500), t.noise_um);
    const Score sa = score(t, after);
    std::string why;
    const bool decided = decided_for_truth(t, after, competitor_of(t, *d.plan), &why);
    std::cout << "seed " << seed << ": " << option_text(m) << "\n  before: " << s.report << "\n  after (" << why
              << "): " << sa.report << "\n";
    EXPECT_TRUE(decided) << why << "\n" << sa.report;
    EXPECT_FALSE(sa.false_culprit) << sa.report;
  }
}

// Issue 28: `plan --layout traces` — the same separable pair (thermal drift vs wear at 1.5 µm noise, teeth 1 and 18)
// planned as a measuring machine takes it: 3 profile traces at face-width positions and 3 helix traces at diameters
// per flank. The plan must expect to resolve it with traces; followed literally (its teeth, its trace positions, the
// truth computed here, a new noise seed) the diagnosis names thermal drift alone.
TEST(HiddenEffectsIndependent, ThermalDriftVersusWearPlannedAsTracesIsResolvedByThoseTraces) {
  const Truth t{"thermal drift X 9 um, tau 600 s at 1.5 um noise", {"thermal_drift"}, true, thermal(9.0, 0.0, 600.0),
                {{"thermal_drift.x_growth_um", 9.0}}, 0.0, 0.0, 1.5, true};
  diagnosis::DiagnoseOptions o;
  o.noise_um = t.noise_um;
  o.plan_layout = diagnosis::DiagnoseOptions::PlanLayout::Traces;
  const std::uint64_t seed = 31;
  const auto pts = measure(two_teeth(), t, seed);
  const auto d = diagnosis::diagnose(bench().setup, bench().process(), pts, {}, o);
  const Score s = score(t, d);
  ASSERT_TRUE(s.ambiguous && s.right) << s.report;
  ASSERT_TRUE(d.plan.has_value());
  const auto& m = d.plan->recommended;
  ASSERT_TRUE(m.traces);
  EXPECT_EQ(m.profile_z_mm.size(), 3u);
  EXPECT_EQ(m.helix_diameter_mm.size(), 3u);
  EXPECT_EQ(m.points, static_cast<int>(m.teeth.size()) * 2 * 6 * m.points_per_trace);
  EXPECT_TRUE(m.resolves);
  EXPECT_GE(std::min(m.delta_bic_if_first, m.delta_bic_if_second), o.plan_target_delta_bic);
  EXPECT_NE(d.verdict.find("3 profile traces (z = "), std::string::npos) << d.verdict;
  auto after_pts = pts;
  const auto more = measure(trace_layout(m.teeth, m.profile_z_mm, m.helix_diameter_mm, m.points_per_trace), t, seed + 500);
  after_pts.insert(after_pts.end(), more.begin(), more.end());
  const auto after = run(after_pts, t.noise_um);
  const Score sa = score(t, after);
  std::string why;
  const bool decided = decided_for_truth(t, after, competitor_of(t, *d.plan), &why);
  for (const auto& op : d.plan->options) // what was scored, for the docs' numbers
    std::cout << "  option: " << op.teeth.size() << " teeth, " << op.points << " points, expected gap "
              << op.delta_bic_if_first << " / " << op.delta_bic_if_second << "\n";
  if (std::getenv("GEARTOPO_TEST_VERBOSE")) std::cout << d.verdict << "\n";
  std::cout << "traces: teeth " << m.teeth.size() << ", " << m.points << " points, expected gap " << m.delta_bic_if_first
            << " / " << m.delta_bic_if_second << "\n  after (" << why << "): " << sa.report << "\n";
  EXPECT_TRUE(decided) << why << "\n" << sa.report;
  EXPECT_FALSE(sa.false_culprit) << sa.report;
}

// ---- other gears and set-ups (issue 27: "5/5 on other gears and set-ups") ----

namespace {

/// The default scene's text with `from` replaced by `to` (each must occur once), built into a workbench once.
const workbench::Workbench& variant(const std::vector<std::pair<std::string, std::string>>& edits) {
  static std::map<std::string, std::unique_ptr<workbench::Workbench>> built;
  std::string key;
  for (const auto& [from, to] : edits) key += from + "→" + to + ";";
  auto& slot = built[key];
  if (!slot) {
    std::ifstream in(kSceneFile);
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    for (const auto& [from, to] : edits) {
      const auto at = s.find(from);
      EXPECT_NE(at, std::string::npos) << from;
      EXPECT_EQ(s.find(from, at + 1), std::string::npos) << from;
      s.replace(at, from.size(), to);
    }
    auto sc = scene::parse_scene(s, kSceneFile);
    sc.grid.measured_file.clear(); // the demo measurement belongs to the default gear
    slot = std::make_unique<workbench::Workbench>(std::move(sc));
  }
  return *slot;
}

struct OtherSetUp {
  std::string name;
  const workbench::Workbench* wb;
  std::vector<int> teeth;
};

} // namespace

// The library's effects and pairs, written here from their physics (not the plug-ins), measured on set-ups the core set
// does not use: a left-hand gear, skip indexing (every 3rd space: the time order of the teeth changes), other teeth
// (5 and 22, 17 apart), and another gear (m_n 6, z 47, β −20°, b 60 mm: module, size, hand and face width all differ);
// outside the library the A-axis drift and the wheel's edge wear. Scored like the core set: right, no false culprit;
// an ambiguous verdict that lists the truth is right; outside the library the element (or its class) or "unexplained".
TEST(HiddenEffectsIndependent, OtherGearsAndSetUpsMeetTheTargets) {
  const std::vector<OtherSetUp> setups = {
      {"left hand", &variant({{"helix_angle_deg: 30 ", "helix_angle_deg: -30 "}, {"hand: right", "hand: left"}}), {1, 18}},
      {"skip indexing 3", &variant({{"index_step: 1 ", "index_step: 3 "}}), {1, 18}},
      {"teeth 5 and 22", &bench(), {5, 22}},
      {"m_n 6, z 47, beta -20", &variant({{"normal_module_mm: 14", "normal_module_mm: 6"},
                                          {"teeth: 35", "teeth: 47"},
                                          {"helix_angle_deg: 30 ", "helix_angle_deg: -20 "},
                                          {"hand: right", "hand: left"},
                                          {"profile_shift: 0.274", "profile_shift: 0"},
                                          {"face_width_mm: 150 ", "face_width_mm: 60 "},
                                          {"tip_diameter_mm: 601.4753", "tip_diameter_mm: 312.0980"},
                                          {"root_diameter_mm: 538.4753", "root_diameter_mm: 285.0980"}}),
       {1, 24}},
  };
  int cases = 0, right = 0, false_culprits = 0;
  std::string reports;
  std::uint64_t seed = 700;
  for (const auto& su : setups) {
    const auto l = make_layout(su.teeth, 7, 9, *su.wb);
    const double b = su.wb->setup.geometry().spec().face_width_mm;
    const std::vector<Truth> truths = {
        {"noise only", {}, true, nullptr, {}},
        {"thermal drift X 9 um, Z 4 um, tau 600 s", {"thermal_drift"}, true, thermal(9.0, 4.0, 600.0), {}},
        {"wheel wear 0.25 um/stroke", {"wheel_wear"}, true, wear(0.25), {}},
        {"eccentricity (6, -4) um", {"eccentricity"}, true, eccentric(6.0, -4.0), {}},
        {"wear 0.25 um/stroke + eccentricity (6, -4) um", {"eccentricity", "wheel_wear"}, true,
         [w = wear(0.25), e = eccentric(6.0, -4.0)](const Contact& c) { return w(c) + e(c); }, {}},
        {"thermal drift X 9 um, tau 600 s + arbor deflection 6 um", {"deflection", "thermal_drift"}, true,
         [th = thermal(9.0, 0.0, 600.0), de = arbor_deflection(6.0, 600.0, b)](const Contact& c) { return th(c) + de(c); },
         {}},
        {"swivel drift 20 urad/stroke (outside the library)", {}, false, swivel_drift(20.0), {}, 0.0, 0.0, 0.5, false,
         false, {"E_AOA linear_in_time", "epsilon_xa linear_in_time"}},
        {"edge wear 0.4 um/stroke (outside the library)", {}, false, edge_wear(0.4), {}, 0.0, 0.0, 0.5, false, false,
         {"wheel_profile_wear"}},
    };
    for (const auto& t : truths) {
      // Outside the library: seeds of their own, so the library cases keep theirs.
      const std::uint64_t case_seed = t.in_library ? ++seed : 1000 + seed + static_cast<std::uint64_t>(&t - truths.data());
      const auto d = run(measure(l, t, case_seed, *su.wb), t.noise_um, *su.wb);
      const Score s = score(t, d);
      ++cases;
      right += s.right;
      false_culprits += s.false_culprit;
      reports += std::string(s.right ? "  ok    " : "  WRONG ") + "[" + su.name + "] " + s.report + "\n";
    }
  }
  std::cout << reports << "tally: " << right << " of " << cases << " right, " << false_culprits << " false culprits\n";
  EXPECT_EQ(false_culprits, 0) << reports;
  EXPECT_GE(right, 0.9 * cases) << reports; // the core set's target; docs/diagnosis.md has the tally over more seeds
}

// Issue 28: the same hidden effects (written here from their physics, not the plug-ins) measured two ways on teeth 1
// and 18 — the 7 × 9 grid per flank, and as a measuring machine takes traces (three profile traces at z = 20, 75,
// 130 mm and two helix traces at 40 % and 70 % of the active profile, 100 points each) — at the same 0.5 µm noise:
// diagnose names the truth on both, with no false culprit (outside the library: the A-axis drift's element or class).
TEST(HiddenEffectsIndependent, TheSameEffectsMeasuredAsGridAndAsTracesGiveTheSameDiagnosis) {
  const auto& g = bench().setup.geometry();
  const double xa = g.roll_length_at(g.root_form_diameter_mm()), xe = g.roll_length_at(g.tip_diameter_mm());
  const Layout traces = trace_layout({1, 18}, {20.0, 75.0, 130.0},
                                     {g.diameter_at_roll_length(xa + 0.4 * (xe - xa)), g.diameter_at_roll_length(xa + 0.7 * (xe - xa))},
                                     100);
  const std::vector<Truth> truths = {
      {"thermal drift X 9 um, Z 4 um, tau 600 s", {"thermal_drift"}, true, thermal(9.0, 4.0, 600.0), {}},
      {"wheel wear 0.25 um/stroke", {"wheel_wear"}, true, wear(0.25), {}},
      {"eccentricity (6, -4) um", {"eccentricity"}, true, eccentric(6.0, -4.0), {}},
      {"noise only", {}, true, nullptr, {}},
      {"swivel drift 20 urad/stroke (outside the library)", {}, false, swivel_drift(20.0), {}, 0.0, 0.0, 0.5, false, false,
       {"E_AOA linear_in_time", "epsilon_xa linear_in_time"}},
  };
  std::uint64_t seed = 900;
  for (const auto& t : truths) {
    const Score on_grid = score(t, run(measure(two_teeth(), t, ++seed), t.noise_um));
    const Score on_traces = score(t, run(measure(traces, t, ++seed), t.noise_um));
    std::cout << "  grid:   " << on_grid.report << "\n  traces: " << on_traces.report << "\n";
    EXPECT_TRUE(on_grid.right && !on_grid.false_culprit) << on_grid.report;
    EXPECT_TRUE(on_traces.right && !on_traces.false_culprit) << on_traces.report;
  }
}
