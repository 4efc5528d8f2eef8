// geartopo tests — measured traces end to end (issue 28): counts that agree between the console and compare.json, and
// the residual analysis on traces as a measuring machine takes them (a few dense lines per flank, gaps), on exports
// written from the documented structure (trace_export_fixture.hpp) with known answers. Units: mm, µm.
#include "../trace_export_fixture.hpp"

#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/report/measurement_report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <numbers>
#include <random>

using namespace geartopo;
using namespace trace_fixture;

namespace {

constexpr double kPi = std::numbers::pi;

struct Read {
  std::vector<measurement::MeasuredPoint> points;
  measurement::ReadCounts counts;
};

Read read_export(const Export& e) {
  TempFile f("measured.mka", e.text);
  Read r;
  r.points = measurement::read_any_measurement(f.path.string(), ideal_workbench().setup, nullptr, {}, &r.counts);
  return r;
}

bool inside_ranges(const gears::EvaluationRanges& r, double xi, double z) {
  const double s = 1e-3;
  return xi >= r.xi_eval_start_mm - s && xi <= r.xi_eval_end_mm + s && z >= r.z_eval_start_mm - s && z <= r.z_eval_end_mm + s;
}

/// Three profile traces and two helix traces per flank, as a measuring machine takes them on a large gear.
Layout three_profiles_two_helices() {
  const auto& g = ideal_workbench().setup.geometry();
  Layout l;
  l.profile_z_mm = {20.0, 75.0, 130.0};
  const double xa = g.roll_length_at(g.root_form_diameter_mm()), xe = g.roll_length_at(g.tip_diameter_mm());
  l.helix_d_mm = {g.diameter_at_roll_length(xa + 0.4 * (xe - xa)), g.diameter_at_roll_length(xa + 0.7 * (xe - xa))};
  return l;
}

/// The residual of every flank of an export on the ideal machine, with the scene's evaluation ranges.
std::vector<diagnosis::FlankResiduals> flanks_of(const Read& r) {
  std::vector<double> residual;
  for (const auto& p : r.points) residual.push_back(p.deviation_um); // ideal machine: the model is the design
  return diagnosis::flank_residuals(ideal_workbench().setup.ranges(), r.points, residual);
}

diagnosis::FlankPatterns patterns_of(const diagnosis::FlankResiduals& f, double sigma) {
  diagnosis::PatternOptions o;
  o.noise_um = sigma;
  return diagnosis::fit_flank_patterns(f, o);
}

} // namespace

// -------------------------------------------------------------------------------------------- one count, one truth

// The measurement: three profile and two helix traces on both flanks of teeth 1 and 18, measured beyond the
// evaluation ranges, one undefined value — and its last trace read twice. An export that repeats a trace is refused
// by its reader (docs/measurement-formats.md), so the repeat is appended here to the points read, as a traces CSV can
// hold it. The counts are checked against what the fixture wrote and where its points lie (computed here), and the
// console text carries exactly the JSON's numbers.
TEST(TraceCounts, ConsoleAndJsonCountTheSamePointsAndSayWhatIsLeftOut) {
  const auto& wb = ideal_workbench();
  Layout l = three_profiles_two_helices();
  l.profile_points = 24, l.helix_points = 24;
  l.undefined = {{0, 5}};
  const auto e = write_export(wb.setup.geometry(), l, [](Flank s, int, double, double) { return s == Flank::Left ? 1.5 : -1.5; });
  const auto r = read_export(e);
  EXPECT_EQ(r.counts.undefined_values, 1u);
  ASSERT_EQ(r.points.size(), e.values - e.undefined);
  auto pts = r.points;
  const std::size_t repeated = static_cast<std::size_t>(l.helix_points); // the last trace, read again
  const std::vector<measurement::MeasuredPoint> copy(pts.end() - static_cast<std::ptrdiff_t>(repeated), pts.end());
  pts.insert(pts.end(), copy.begin(), copy.end());
  std::size_t outside = 0, repeated_outside = 0;
  for (const auto& p : pts) outside += !inside_ranges(wb.setup.ranges(), p.roll_length_mm, p.z_mm);
  for (const auto& p : copy) repeated_outside += !inside_ranges(wb.setup.ranges(), p.roll_length_mm, p.z_mm);
  ASSERT_GT(outside, 0u);

  const auto c = diagnosis::compare(wb.setup, wb.process(), pts, 0.0, r.counts);
  EXPECT_EQ(c.counts.read, pts.size());
  EXPECT_EQ(c.counts.duplicates, repeated);
  EXPECT_EQ(c.counts.outside_evaluation_range, outside - repeated_outside);
  EXPECT_EQ(c.counts.used, pts.size() - (outside - repeated_outside) - repeated);
  EXPECT_EQ(c.counts.undefined_values, 1u);

  const auto j = report::compare_json("scene.yaml", "measured.mka", pts, c);
  const auto text = report::compare_summary_text(c);
  EXPECT_EQ(j["overall"]["points"].get<std::size_t>(), c.counts.used);
  EXPECT_EQ(j["point_counts"]["read"].get<std::size_t>(), c.counts.read);
  EXPECT_EQ(j["point_counts"]["duplicates"].get<std::size_t>(), repeated);
  EXPECT_EQ(j["point_counts"]["undefined_values"].get<std::size_t>(), 1u);
  // The same sentence in both, and every number the console prints is the JSON's.
  EXPECT_NE(text.find(j["point_counts"]["sentence"].get<std::string>()), std::string::npos) << text;
  EXPECT_NE(text.find(fmt::format("{} measured points read: {} used", c.counts.read, c.counts.used)), std::string::npos) << text;
  EXPECT_NE(text.find("1 undefined value"), std::string::npos) << text;
  EXPECT_NE(text.find(fmt::format("over the {} used points", j["overall"]["points"].get<std::size_t>())), std::string::npos) << text;
  EXPECT_NE(text.find(fmt::format("{:.2f} µm RMS", j["overall"]["rms_um"].get<double>())), std::string::npos) << text;
  EXPECT_NE(text.find(fmt::format("extreme {:+.2f} µm", j["overall"]["extreme_um"].get<double>())), std::string::npos) << text;
  std::size_t per_flank = 0;
  for (const auto& f : j["flanks"]) {
    const auto line = fmt::format("{:>5} points used ({} outside, {} duplicates)  RMS {:6.2f} µm  extreme {:+7.2f} µm",
                                  f["stats"]["points"].get<std::size_t>(), f["points_outside_evaluation_range"].get<std::size_t>(),
                                  f["duplicates"].get<std::size_t>(), f["stats"]["rms_um"].get<double>(),
                                  f["stats"]["extreme_um"].get<double>());
    EXPECT_NE(text.find(line), std::string::npos) << line << "\n" << text;
    per_flank += f["stats"]["points"].get<std::size_t>();
  }
  EXPECT_EQ(per_flank, c.counts.used);
  // 1.5 µm along the normal everywhere, plus and minus: RMS and extreme exact (the file's 4 decimals: 1e-4 µm).
  EXPECT_NEAR(j["overall"]["rms_um"].get<double>(), 1.5, 1e-4);
}

// --------------------------------------------------------------------------------- patterns on traces, known answers

// Constant traces: no noise (σ at its floor), no waviness, no slope or crowning; the offset is the value; profile and
// helix lines agree where they cross.
TEST(TracePatterns, ConstantTracesGiveTheOffsetAndNothingElse) {
  const auto& wb = ideal_workbench();
  const auto e = write_export(wb.setup.geometry(), three_profiles_two_helices(),
                              [](Flank s, int, double, double) { return s == Flank::Left ? 1.77 : -1.77; });
  const auto r = read_export(e);
  const auto c = diagnosis::compare(wb.setup, wb.process(), r.points, 0.0, r.counts);
  EXPECT_LE(c.noise_um, 2e-3);
  ASSERT_EQ(c.flanks.size(), 4u);
  for (std::size_t f = 0; f < c.flanks.size(); ++f) {
    ASSERT_TRUE(c.has_patterns[f]);
    const auto& p = c.patterns[f];
    SCOPED_TRACE(diagnosis::describe_patterns(p));
    EXPECT_NEAR(p.offset_um.value, p.side == Flank::Left ? 1.77 : -1.77, 1e-3);
    for (const auto n : {diagnosis::NamedPattern::ProfileSlope, diagnosis::NamedPattern::HelixSlope, diagnosis::NamedPattern::Twist,
                         diagnosis::NamedPattern::ProfileCrowning, diagnosis::NamedPattern::HelixCrowning})
      EXPECT_NEAR(diagnosis::pattern_value(p, n).value, 0.0, 1e-3);
    EXPECT_FALSE(p.waviness_profile.wave.has_value());
    EXPECT_FALSE(p.waviness_helix.wave.has_value());
  }
  ASSERT_EQ(c.line_agreement.size(), 4u);
  for (const auto& a : c.line_agreement) EXPECT_FALSE(a.disagree) << a.sentence;
}

// Linear and parabolic traces: offset, slopes, twist and crownings as written, to 0.05 µm, from three profile and
// two helix lines per flank with gaps (undefined values).
TEST(TracePatterns, LinearAndParabolicTracesGiveTheirSlopesAndCrownings) {
  const auto& wb = ideal_workbench();
  const auto& r0 = wb.setup.ranges();
  const double x0 = r0.xi_eval_start_mm, x1 = r0.xi_eval_end_mm, z0 = r0.z_eval_start_mm, z1 = r0.z_eval_end_mm;
  // Known patterns (flank_patterns.hpp): offset a, profile slope s_a (rise across L_α), helix slope s_b, twist t,
  // crownings C_a, C_b (middle above the ends), on the normalised u, w of the evaluation ranges.
  const double a = 0.8, s_a = 3.0, s_b = -2.0, t = 1.5, C_a = 4.0, C_b = -2.5;
  const auto truth = [&](Flank, int, double xi, double z) {
    const double u = 2 * (xi - x0) / (x1 - x0) - 1, w = 2 * (z - z0) / (z1 - z0) - 1;
    return a + s_a / 2 * u + s_b / 2 * w + t / 4 * u * w + C_a * (1.0 / 3 - u * u) + C_b * (1.0 / 3 - w * w);
  };
  Layout l = three_profiles_two_helices();
  l.undefined = {{0, 50}, {0, 51}, {1, 120}, {3, 10}, {4, 200}};
  const auto r = read_export(write_export(wb.setup.geometry(), l, truth));
  for (const auto& f : flanks_of(r)) {
    const auto p = patterns_of(f, 0.05);
    SCOPED_TRACE(diagnosis::describe_patterns(p));
    EXPECT_NEAR(p.offset_um.value, a, 0.05);
    EXPECT_NEAR(p.profile_slope_um.value, s_a, 0.05);
    EXPECT_NEAR(p.helix_slope_um.value, s_b, 0.05);
    EXPECT_NEAR(p.twist_um.value, t, 0.05);
    EXPECT_NEAR(p.profile_crowning_um.value, C_a, 0.05);
    EXPECT_NEAR(p.helix_crowning_um.value, C_b, 0.05);
  }
}

// Sinusoidal traces: a profile waviness (amplitude 1.2 µm, wavelength 7 mm) and a helix waviness (0.8 µm, 23 mm) on a
// slope, found by the scan with amplitude to 0.05 µm and wavelength to 1 %; the noise estimated from the lines
// (σ 0.2 µm added) is σ to 10 %.
TEST(TracePatterns, SinusoidalTracesGiveTheirWavinessAmplitudeAndWavelength) {
  const auto& wb = ideal_workbench();
  const auto& rg = wb.setup.ranges();
  const double A_p = 1.2, lambda_p = 7.0, A_h = 0.8, lambda_h = 23.0, sigma = 0.2;
  std::mt19937_64 gen(28);
  std::normal_distribution<double> noise(0.0, sigma);
  const auto truth = [&](Flank, int, double xi, double z) {
    return 0.5 + 0.02 * (xi - rg.xi_eval_start_mm) + A_p * std::sin(2 * kPi * xi / lambda_p) +
           A_h * std::cos(2 * kPi * z / lambda_h) + noise(gen);
  };
  const auto r = read_export(write_export(wb.setup.geometry(), three_profiles_two_helices(), truth));
  std::vector<double> residual;
  for (const auto& p : r.points) residual.push_back(p.deviation_um);
  const double est = diagnosis::estimate_noise_um(r.points, residual);
  EXPECT_NEAR(est, sigma, 0.1 * sigma);
  for (const auto& f : flanks_of(r)) {
    const auto p = patterns_of(f, est);
    SCOPED_TRACE(diagnosis::describe_patterns(p));
    ASSERT_TRUE(p.waviness_profile.wave.has_value());
    ASSERT_TRUE(p.waviness_helix.wave.has_value());
    EXPECT_NEAR(p.waviness_profile.wave->amplitude_um.value, A_p, 0.05);
    EXPECT_NEAR(p.waviness_profile.wave->wavelength_mm, lambda_p, 0.01 * lambda_p);
    EXPECT_NEAR(p.waviness_helix.wave->amplitude_um.value, A_h, 0.05);
    EXPECT_NEAR(p.waviness_helix.wave->wavelength_mm, lambda_h, 0.01 * lambda_h);
  }
}

// Noise only (σ 0.3 µm) on 35 teeth × 2 flanks of traces: σ estimated from the lines to 5 %, and the waviness scan
// reports a wave at most at its stated false-alarm rate α = 10⁻³ per direction and flank (140 scans: 0.14 expected;
// more than 2 has Poisson probability 4·10⁻⁴). The named patterns stay within 4 standard errors of zero.
TEST(TracePatterns, NoiseOnlyTracesGiveNoPatternAtTheStatedFalseAlarmRate) {
  const auto& wb = ideal_workbench();
  const double sigma = 0.3;
  std::mt19937_64 gen(2028);
  std::normal_distribution<double> noise(0.0, sigma);
  Layout l = three_profiles_two_helices();
  l.teeth.clear();
  for (int t = 1; t <= 35; ++t) l.teeth.push_back(t);
  l.profile_points = 120, l.helix_points = 150;
  const auto r = read_export(write_export(wb.setup.geometry(), l, [&](Flank, int, double, double) { return noise(gen); }));
  std::vector<double> residual;
  for (const auto& p : r.points) residual.push_back(p.deviation_um);
  const double est = diagnosis::estimate_noise_um(r.points, residual);
  EXPECT_NEAR(est, sigma, 0.05 * sigma);
  int waves = 0, scans = 0, beyond = 0, regions = 0;
  std::vector<diagnosis::FlankPatterns> left, right;
  diagnosis::RegionOptions ro;
  ro.noise_um = est;
  ro.min_points = 2; // as compare: two failing neighbours of one sign
  for (const auto& f : flanks_of(r)) {
    const auto p = patterns_of(f, est);
    (f.side == Flank::Left ? left : right).push_back(p);
    regions += static_cast<int>(diagnosis::find_failing_regions(f, ro).size());
    EXPECT_DOUBLE_EQ(p.waviness_profile.chi2_threshold > 0 ? 1.0 : 0.0, 1.0);
    scans += p.waviness_profile.scanned + p.waviness_helix.scanned;
    waves += p.waviness_profile.wave.has_value() + p.waviness_helix.wave.has_value();
    for (const auto n : diagnosis::kNamedPatterns)
      if (n != diagnosis::NamedPattern::Offset)
        beyond += std::abs(diagnosis::pattern_value(p, n).value) > 4 * diagnosis::pattern_value(p, n).standard_error;
  }
  EXPECT_EQ(scans, 140);
  EXPECT_LE(waves, 2);
  EXPECT_EQ(beyond, 0);
  // Failing regions: a 3σ point is 0.27 % of 46 200 (125 points), two neighbours of one sign both beyond 3σ about
  // 0.2 pairs in all; tooth trends: every pattern constant over the 35 teeth at 3σ (6 patterns × 2 sides × 0.27 %).
  EXPECT_LE(regions, 2);
  for (const auto* side : {&left, &right}) {
    const auto trends = diagnosis::fit_tooth_trends(*side, 35);
    for (const auto& t : trends.trends) EXPECT_EQ(t.kind, diagnosis::TrendKind::Constant) << t.sentence;
  }
}

// Tooth trends from traces: an offset growing by 0.05 µm per tooth and a profile slope varying once per revolution
// (amplitude 1 µm, largest at tooth 10) over 35 teeth of three profile and two helix traces with 0.3 µm noise.
TEST(TracePatterns, ToothTrendsFromTracesAreFound) {
  const auto& wb = ideal_workbench();
  const auto& rg = wb.setup.ranges();
  const double x0 = rg.xi_eval_start_mm, x1 = rg.xi_eval_end_mm;
  std::mt19937_64 gen(7);
  std::normal_distribution<double> noise(0.0, 0.3);
  const auto theta = [](int tooth) { return 2 * kPi * (tooth - 1) / 35.0; };
  const auto truth = [&](Flank, int tooth, double xi, double) {
    const double u = 2 * (xi - x0) / (x1 - x0) - 1;
    return 0.05 * tooth + 0.5 * std::cos(theta(tooth) - theta(10)) * u + noise(gen);
  };
  Layout l = three_profiles_two_helices();
  l.teeth.clear();
  for (int t = 1; t <= 35; ++t) l.teeth.push_back(t);
  l.profile_points = 120, l.helix_points = 150;
  const auto r = read_export(write_export(wb.setup.geometry(), l, truth));
  std::vector<double> residual;
  for (const auto& p : r.points) residual.push_back(p.deviation_um);
  const double est = diagnosis::estimate_noise_um(r.points, residual);
  std::vector<diagnosis::FlankPatterns> right;
  for (const auto& f : flanks_of(r))
    if (f.side == Flank::Right) right.push_back(patterns_of(f, est));
  const auto t = diagnosis::fit_tooth_trends(right, 35);
  const auto& offset = t.trends[0];
  const auto& slope = t.trends[1];
  EXPECT_EQ(offset.kind, diagnosis::TrendKind::Linear) << offset.sentence;
  EXPECT_NEAR(offset.slope_um_per_tooth.value, 0.05, 0.005) << offset.sentence;
  EXPECT_EQ(slope.kind, diagnosis::TrendKind::OncePerRevolution) << slope.sentence;
  EXPECT_NEAR(slope.amplitude_um.value, 1.0, 0.05) << slope.sentence;
  EXPECT_NEAR(slope.max_at_tooth, 10.0, 0.5) << slope.sentence;
}

// ------------------------------------------------------------------------------------------------------- allowance

// A gear ground to the mean of its designed allowances (A_sne −40 µm, A_sni −80 µm), measured as an export: every flank
// lies Δn = A_sn cos α_n / 2 = −28.19 µm along its normal from the zero-allowance flank (docs/conventions.md: the
// normal thickness at the reference cylinder, an arc in the normal section, which each flank meets at α_n). With the
// allowances in the scene, compare subtracts Δn on both flanks and the residual is zero; without them it is Δn.
TEST(TraceAllowance, TheDesignedAllowanceIsSubtractedOnEveryFlank) {
  const double A_sn_mean_um = (-40.0 + -80.0) / 2, alpha_n = 20.0 * kPi / 180;
  const double dn_um = A_sn_mean_um * std::cos(alpha_n) / 2;
  const workbench::Workbench with(scene::parse_scene(
      ideal_scene_text("  thickness_allowance_upper_um: -40\n  thickness_allowance_lower_um: -80\n"), kDefaultScene));
  const auto e = write_export(with.setup.geometry(), three_profiles_two_helices(), [&](Flank, int, double, double) { return dn_um; });
  TempFile f("allowance.mka", e.text);
  const auto pts = measurement::read_any_measurement(f.path.string(), with.setup);
  const auto c_with = diagnosis::compare(with.setup, with.process(), pts, 0.0);
  const auto c_without = diagnosis::compare(ideal_workbench().setup, ideal_workbench().process(), pts, 0.0);
  EXPECT_NEAR(c_with.allowance_offset_um, -28.19, 0.005);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    ASSERT_NEAR(c_with.residual_um[i], 0.0, 1e-3) << "point " << i; // the file's 4 decimals
    ASSERT_NEAR(c_without.residual_um[i], dn_um, 1e-3) << "point " << i;
  }
  std::set<std::pair<int, int>> flanks;
  for (const auto& p : pts) flanks.insert({p.tooth, static_cast<int>(p.flank)});
  EXPECT_EQ(flanks.size(), 4u); // both flanks of both teeth
}

// Findings on a flank whose profile and helix lines disagree where they cross rest on a disputed sign (issue 39): an
// export read with the wrong sign rule (din for a raw export: the right flanks' helix lines flipped, their profiles
// not) gives the right flanks' lines +1.2 and −1.2 µm where they cross. Each of those flanks' patterns (console and
// compare.json) and failing regions says it rests on the disputed sign; the left flanks (both lines flipped alike:
// they agree) say nothing of the kind.
TEST(TracePatterns, FindingsOnAFlankWhoseLinesDisagreeSayTheyRestOnADisputedSign) {
  const auto& wb = ideal_workbench();
  const auto e = write_export(wb.setup.geometry(), three_profiles_two_helices(), [](Flank, int, double xi, double) {
    return 1.2 + 0.05 * (xi - 100.0); // a profile slope, so that the right flanks' regions grow along the profile
  });
  TempFile f("measured.mka", e.text);
  measurement::KlingelnbergOptions din;
  din.signs = measurement::SignConvention::Din;
  measurement::ReadCounts counts;
  const auto pts = measurement::read_any_measurement(f.path.string(), wb.setup, nullptr, din, &counts);
  const auto c = diagnosis::compare(wb.setup, wb.process(), pts, 0.05, counts);
  ASSERT_EQ(c.disputed_sign.size(), c.flanks.size());
  const auto j = report::compare_json("scene.yaml", "measured.mka", pts, c);
  const auto text = report::compare_summary_text(c);
  const std::string note = diagnosis::kDisputedSignNote;
  std::size_t disputed = 0;
  for (std::size_t k = 0; k < c.flanks.size(); ++k) {
    const bool right = c.flanks[k].side == Flank::Right;
    SCOPED_TRACE(fmt::format("tooth {} {}", c.flanks[k].tooth, diagnosis::to_string(c.flanks[k].side)));
    EXPECT_EQ(c.disputed_sign[k], right);
    disputed += c.disputed_sign[k];
    EXPECT_EQ(j["flanks"][k]["rests_on_disputed_sign"].get<bool>(), right);
    ASSERT_TRUE(c.has_patterns[k]);
    const std::string line = diagnosis::describe_patterns(c.patterns[k]);
    EXPECT_EQ(text.find(line + note) != std::string::npos, right) << text;
    EXPECT_EQ(j["flanks"][k]["description"].get<std::string>(), line + (right ? note : ""));
  }
  EXPECT_EQ(disputed, 2u); // the right flanks of teeth 1 and 18
  ASSERT_FALSE(c.regions.empty());
  for (const auto& r : c.regions) {
    const bool ends_with_note = r.sentence.size() > note.size() && r.sentence.ends_with(note);
    EXPECT_EQ(ends_with_note, r.side == Flank::Right) << r.sentence;
  }
}

// A Klingelnberg export carries no design line (issue 39, part 2): read as it is, its values are the flank from the bare
// involute and nobody said so (reference_declared false); declared "against: design" each point keeps its value as the
// deviation from the scene's drawing — the two readings differ by exactly the design at the point — and declared
// "involute" it reads as before, but declared.
TEST(TraceReference, AnExportDeclaredAgainstTheDesignKeepsItsValuesAsDeviationsFromTheDrawing) {
  const workbench::Workbench wb(scene::parse_scene(
      ideal_scene_text("  modifications:\n    both: {profile_crowning_um: 4, helix_crowning_um: 6}\n"), kDefaultScene));
  const auto e = write_export(wb.setup.geometry(), three_profiles_two_helices(), [](Flank, int, double, double) { return 0.3; });
  TempFile f("measured.mka", e.text);
  const auto read = [&](measurement::MeasuredAgainst against) {
    return measurement::read_any_measurement(f.path.string(), wb.setup, nullptr, {}, nullptr, against);
  };
  const auto as_file = read(measurement::MeasuredAgainst::as_file);
  const auto design = read(measurement::MeasuredAgainst::design);
  const auto involute = read(measurement::MeasuredAgainst::involute);
  ASSERT_EQ(as_file.size(), design.size());
  ASSERT_EQ(as_file.size(), involute.size());
  double largest_design_um = 0.0;
  for (std::size_t i = 0; i < as_file.size(); ++i) {
    const auto& p = as_file[i];
    const double d = wb.setup.design().at_um(p.flank, p.roll_length_mm, p.z_mm); // the drawing there, computed anew
    largest_design_um = std::max(largest_design_um, std::abs(d));
    EXPECT_NEAR(design[i].deviation_um - p.deviation_um, d, 1e-9);
    EXPECT_NEAR(design[i].deviation_um, 0.3, 1e-3); // the export's value (4 decimals, transverse → normal)
    EXPECT_EQ(involute[i].deviation_um, p.deviation_um);
    EXPECT_FALSE(p.reference_declared);
    EXPECT_TRUE(design[i].reference_declared);
    EXPECT_TRUE(involute[i].reference_declared);
  }
  EXPECT_GT(largest_design_um, 2.0); // the crownings show (C_α 4, C_β 6 µm)
}
