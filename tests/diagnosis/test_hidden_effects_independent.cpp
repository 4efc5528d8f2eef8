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
// is in the library. Run time: 12 cases × 2 seeds, each one `diagnose` on 126 points (≈ 1–2 s each, Release).
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <iostream>
#include <sstream>

using namespace geartopo;

namespace independent_truth {

const std::string kSceneFile = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";

const workbench::Workbench& bench() {
  static const workbench::Workbench b(kSceneFile);
  return b;
}

/// Where and when a measured point was ground: its nominal flank point and the generating pose of the path.
struct Contact {
  gears::FlankPoint fp;
  grinding::PathPoint pp;
  double strokes_before = 0.0; ///< strokes completed before this point's stroke, plus the progress along it (0 … 1)
  double profile_fraction = 0.0; ///< 0 at the smallest measured roll length (root end), 1 at the largest (tip end)
};

/// A noise-free measurement of the scene as modelled (the simulator's exact deviation) on the given teeth, with the
/// contact of every point. Built once per layout.
struct Layout {
  std::vector<diagnosis::MeasuredPoint> points;
  std::vector<Contact> contacts;
};

Layout make_layout(const std::vector<int>& teeth, int rows, int cols) {
  const auto& s = bench().setup;
  diagnosis::SynthOptions o;
  o.teeth = teeth;
  o.rows = rows;
  o.cols = cols;
  o.noise_um = 0.0;
  Layout l;
  l.points = diagnosis::measured_points(diagnosis::synthesize(s, bench().process(), o), s.geometry(), "independent");
  const grinding::IdealProcess ideal;
  const grinding::FlankDeviation generating(s.flanks(), s.wheel(), s.path(), ideal);
  for (const auto& p : l.points) {
    Contact c;
    c.fp = s.flanks().at(p.tooth, p.flank, p.roll_length_mm, p.z_mm);
    const int space = grinding::space_of(p.tooth, p.flank, s.geometry().teeth());
    const double z0 = generating.at(p.tooth, p.flank, p.roll_length_mm, p.z_mm, grinding::Method::Linear).z_stroke_mm;
    c.pp = s.path().point(space, z0);
    c.strokes_before = s.path().stroke_index(space) + std::clamp(s.path().stroke_progress(space, z0), 0.0, 1.0);
    l.contacts.push_back(c);
  }
  double lo = 1e300, hi = -1e300;
  for (const auto& p : l.points) lo = std::min(lo, p.roll_length_mm), hi = std::max(hi, p.roll_length_mm);
  for (size_t i = 0; i < l.points.size(); ++i) l.contacts[i].profile_fraction = (l.points[i].roll_length_mm - lo) / (hi - lo);
  return l;
}

const Layout& two_teeth() { // teeth 1 and 18 (half a turn apart), 7 × 9 grid per flank, both flanks: 252 points
  static const Layout l = make_layout({1, 18}, 7, 9);
  return l;
}

/// Normal deviation (µm, plus material positive) of the wheel moved by axis offsets δq at the contact.
double axis_offset_um(const Contact& c, const machine::AxisPose& dq) {
  machine::AxisPose q = c.pp.q;
  q.x += dq.x, q.y += dq.y, q.z += dq.z, q.a += dq.a, q.c += dq.c;
  const Eigen::Vector3d moved = machine::ideal_wMg(q) * (machine::ideal_wMg(c.pp.q).inverse() * c.fp.p);
  return 1e3 * (moved - c.fp.p).dot(c.fp.n);
}

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
};

/// The outcome of one case, scored against its truth.
struct Score {
  bool right = false, false_culprit = false, ambiguous = false;
  int parameters_checked = 0, parameters_within = 0;
  bool residual_checked = false, residual_ok = false;
  std::string report;
};

std::vector<diagnosis::MeasuredPoint> measure(const Layout& l, const Truth& t, std::uint64_t seed) {
  const auto& g = bench().setup.geometry();
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
  const bool unexplained = d.verdict.find("unexplained") != std::string::npos;
  s.ambiguous = !d.rivals.empty();
  // The explanations the verdict names: the chosen one, and its rivals when it says "ambiguous".
  std::vector<const diagnosis::Candidate*> named;
  if (d.chosen) named.push_back(&*d.chosen);
  for (const auto& r : d.rivals) named.push_back(&r);
  const diagnosis::Candidate* truth_named = nullptr;
  bool foreign = false; // a named explanation holds an effect that is not hidden
  for (const auto* c : named) {
    if (sorted_types(*c) == t.effects) truth_named = c;
    for (const auto& n : sorted_types(*c))
      foreign |= std::find(t.effects.begin(), t.effects.end(), n) == t.effects.end();
    why << (c == named.front() ? "chose " : " | rival ") << c->name();
  }
  if (named.empty()) why << "chose nothing";
  if (!t.in_library) {
    // Outside the library: naming an effect is a false culprit unless the verdict also says what is left is
    // unexplained and the named values are plausible and off their bounds (a partial explanation, said as such).
    s.false_culprit = d.chosen && (!unexplained || !d.chosen->rejected.empty() || on_a_bound(*d.chosen));
    s.right = !s.false_culprit && unexplained;
  } else if (t.effects.empty()) {
    s.false_culprit = d.chosen.has_value();
    s.right = !d.chosen;
  } else {
    s.right = truth_named != nullptr;
    // Ambiguous between the truth and something else is no false culprit; naming only wrong explanations is.
    s.false_culprit = foreign && truth_named == nullptr;
  }
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

diagnosis::Diagnosis run(const std::vector<diagnosis::MeasuredPoint>& pts, double noise_um) {
  diagnosis::DiagnoseOptions o;
  o.noise_um = noise_um;
  return diagnosis::diagnose(bench().setup, bench().process(), pts, {}, o);
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
      {"swivel drift 20 urad/stroke (outside the library)", {}, false, swivel_drift(20.0), {}},
      {"edge wear 0.4 um/stroke (outside the library)", {}, false, edge_wear(0.4), {}},
  };
}

} // namespace independent_truth

using namespace independent_truth;

// The whole set, two seeds per case, scored together against the targets of issue 14. Every ambiguous verdict on a
// library truth is followed: the plan's two best teeth are measured as well (same truth, another seed), and the
// diagnosis on the four teeth must name the truth alone.
TEST(HiddenEffectsIndependent, DiagnosisMeetsTheTargetsOverTheSet) {
  int cases = 0, right = 0, false_culprits = 0, params = 0, params_within = 0, residuals = 0, residuals_ok = 0;
  int followed = 0, resolved = 0;
  std::string reports;
  std::uint64_t case_seed = 100;
  for (const auto& t : library_set())
    for (std::uint64_t seed : {++case_seed, case_seed + 1000}) { // each case its own noise
      const auto pts = measure(two_teeth(), t, seed);
      double hidden_ss = 0.0;
      for (const auto& c : two_teeth().contacts) hidden_ss += t.hidden ? std::pow(t.hidden(c), 2) : 0.0;
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
      if (!(s.ambiguous && t.in_library && d.plan && !d.plan->recommended_teeth.empty())) continue;
      ++followed;
      std::vector<int> teeth{1, 18};
      std::string list;
      for (int tooth : d.plan->recommended_teeth) teeth.push_back(tooth), list += std::to_string(tooth) + " ";
      const Score after = score(t, run(measure(make_layout(teeth, 3 * 7, 3 * 9), t, seed + 1), t.noise_um));
      const bool ok = after.right && !after.ambiguous && !after.false_culprit && after.residual_ok;
      resolved += ok;
      reports += std::string(ok ? "    resolved by teeth " : "    NOT resolved by teeth ") + list + "(expected " +
                 std::to_string(d.plan->recommended_separation_sigma) + " sigma): " + after.report + "\n";
    }
  std::cout << reports;
  EXPECT_EQ(false_culprits, 0) << reports;
  EXPECT_GE(right, 0.9 * cases) << right << " of " << cases << " right\n" << reports;
  EXPECT_GE(params_within, 0.9 * params) << params_within << " of " << params << " parameters within 2σ\n" << reports;
  EXPECT_EQ(residuals_ok, residuals) << residuals_ok << " of " << residuals << " residuals within 1.5× noise\n" << reports;
  EXPECT_EQ(resolved, followed) << "ambiguous verdicts resolved by the recommended teeth\n" << reports;
}
