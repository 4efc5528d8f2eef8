// geartopo tests — the measuring machine's own profile and helix values (a value file, .mew) beside geartopo's
// evaluation of the same traces (workbench::compare_machine_flank_values). The export's traces have analytic shapes and
// the value files carry numbers computed here from the closed forms, not by geartopo's evaluator:
//   a trace s·u + a·u² (u from the middle of a range of length L) has over that range the least-squares slope s, so
//   f_H = s·L; its residual a·(u² − L²/12) has the peak-to-valley f_f = |a|·L²/4; F = max − min of s·u + a·u² over the
//   range (ends and, when inside, the vertex u* = −s/(2a)). Over another range [u1, u2] the slope is s + a·(u1 + u2).
// Units: mm, µm.
#include "../cli_run.hpp"
#include "../trace_export_fixture.hpp"

#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/measurement/klingelnberg_values.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/workbench/machine_flank_values.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>

using namespace geartopo;
using namespace trace_fixture;
using measurement::MachineQuantity;
using workbench::MachineCause;

// Its own namespace: test_traces is a unity build with test_trace_patterns.cpp (kPi, beside, …).
namespace flank_values_test {
namespace {

constexpr double kPi = std::numbers::pi;

/// The shape of one flank: targets over the scene's L_α, L_β (reported: transverse, ISO sign rules).
struct Shape {
  double f_Ha, f_fa, f_Hb, f_fb; ///< µm
};

/// Teeth 1 and 18, left and right; the forms ≥ 1 µm and slopes of several µm, so that every convention differs by
/// more than 0.1 µm. Some parabolas have their vertex inside the range (F > |f_H|), some outside (F = |f_H|).
Shape shape(int tooth, Flank side) {
  const int k = (tooth == 1 ? 0 : 2) + (side == Flank::Left ? 0 : 1);
  const std::array<Shape, 4> s{{{5.0, 1.2, -3.5, 1.6}, {-3.5, 1.8, 4.4, 1.1}, {4.2, 1.0, 2.6, 2.2}, {-6.1, 1.4, -5.2, 1.3}}};
  return s[static_cast<std::size_t>(k)];
}

/// max − min of s·u + a·u² over [u1, u2] (µm): the ends and the vertex when it lies inside.
double total(double s, double a, double u1, double u2) {
  const auto f = [&](double u) { return s * u + a * u * u; };
  double lo = std::min(f(u1), f(u2)), hi = std::max(f(u1), f(u2));
  if (a != 0.0) {
    const double v = -s / (2 * a);
    if (v > u1 && v < u2) lo = std::min(lo, f(v)), hi = std::max(hi, f(v));
  }
  return hi - lo;
}

/// A trace's three values over the range [u1, u2] of its own u (measured from the middle of the scene's range).
std::array<double, 3> over(double s, double a, double u1, double u2) {
  const double L = u2 - u1;
  return {(s + a * (u1 + u2)) * L, std::abs(a) * L * L / 4, total(s, a, u1, u2)};
}

struct Fixture {
  std::string mka;
  std::string mka_with_evaluation_range; ///< the same with header lines d1, d2, b1, b2 (not ISO's ranges)
  /// The machine's values per (tooth, flank): f_Hα f_fα F_α f_Hβ f_fβ F_β, over the scene's ranges or the measured ones.
  std::map<std::pair<int, int>, std::array<double, 6>> iso, measured_range, evaluation_range;
  double b_over_L_beta = 0.0, cos_beta_b = 0.0;
};

const Fixture& fixture() {
  static const Fixture fx = [] {
    Fixture f;
    const auto& wb = ideal_workbench();
    const auto& g = wb.setup.geometry();
    const auto r = wb.setup.ranges();
    // β_b from the gear's data (sin β_b = sin β cos α_n), not from the geometry under test
    const double beta = g.spec().helix_angle_rad, alpha_n = g.spec().normal_pressure_angle_rad;
    f.cos_beta_b = std::cos(std::asin(std::sin(beta) * std::cos(alpha_n)));
    const double La = r.xi_eval_end_mm - r.xi_eval_start_mm, Lb = r.z_eval_end_mm - r.z_eval_start_mm;
    const double xm = 0.5 * (r.xi_eval_start_mm + r.xi_eval_end_mm), zm = 0.5 * (r.z_eval_start_mm + r.z_eval_end_mm);
    const double b = g.spec().face_width_mm;
    f.b_over_L_beta = b / Lb;
    const double hand = beta > 0 ? 1.0 : -1.0; // f_Hβ = h σ × rise towards +z (docs/iso1328.md, "Signs")
    const auto sigma = [](Flank s) { return s == Flank::Right ? 1.0 : -1.0; };
    // Profile s·u + a·u² in ξ, helix (rise towards +z) in z; a from f_f = |a| L²/4 (a > 0).
    struct Coef {
      double sa, aa, sb, ab;
    };
    const auto coef = [&](int tooth, Flank side) {
      const Shape s = shape(tooth, side);
      return Coef{s.f_Ha / La, 4 * s.f_fa / (La * La), s.f_Hb / (hand * sigma(side) * Lb), 4 * s.f_fb / (Lb * Lb)};
    };
    Layout l;
    l.profile_z_mm = {0.5 * b};
    const double xa = g.roll_length_at(g.root_form_diameter_mm()), xe = g.roll_length_at(g.tip_diameter_mm());
    l.helix_d_mm = {g.diameter_at_roll_length(0.5 * (xa + xe))};
    l.profile_points = 400, l.helix_points = 500;
    f.mka = write_export(g, l, [&](Flank side, int tooth, double xi, double z) {
              const Coef c = coef(tooth, side);
              const double u = xi - xm, v = z - zm;
              return f.cos_beta_b * (c.sa * u + c.aa * u * u + c.sb * v + c.ab * v * v); // transverse → normal
            }).text;
    // The export's own evaluation range, off ISO's: ξ from 15 % into L_α to 5 % before its end, z 20 … 140 mm.
    const double d1 = g.diameter_at_roll_length(r.xi_eval_start_mm + 0.15 * La);
    const double d2 = g.diameter_at_roll_length(r.xi_eval_end_mm - 0.05 * La), b1 = 20.0, b2 = 140.0;
    f.mka_with_evaluation_range = f.mka;
    const auto at = f.mka_with_evaluation_range.find("  64 :");
    f.mka_with_evaluation_range.insert(at, fmt::format("  42 :Start der Auswertestrecke d1 [mm].: {:.6f}\n"
                                                       "  43 :Ende der Auswertestrecke d2 [mm]..: {:.6f}\n"
                                                       "  62 :Auswerteanfang........b1 [mm].....: {:.6f}\n"
                                                       "  63 :Auswerteende..........b2 [mm].....: {:.6f}\n",
                                                       d1, d2, b1, b2));
    // ξ(d) = ½ √(d² − d_b²)
    const double db = g.base_diameter_mm();
    const auto xi = [&](double d) { return 0.5 * std::sqrt(d * d - db * db); };
    for (const int tooth : l.teeth)
      for (const Flank side : {Flank::Left, Flank::Right}) {
        const Coef c = coef(tooth, side);
        const auto key = std::pair{tooth, static_cast<int>(side)};
        const double hs = hand * sigma(side);
        const auto put = [&](auto& map, double u1, double u2, double v1, double v2) {
          const auto p = over(c.sa, c.aa, u1, u2), h = over(c.sb, c.ab, v1, v2);
          map[key] = {p[0], p[1], p[2], hs * h[0], h[1], h[2]};
        };
        put(f.iso, -La / 2, La / 2, -Lb / 2, Lb / 2);
        put(f.measured_range, xa - xm, xe - xm, -zm, b - zm);
        put(f.evaluation_range, xi(d1) - xm, xi(d2) - xm, b1 - zm, b2 - zm);
      }
    return f;
  }();
  return fx;
}

/// A value file written from the documented structure (docs/measurement-formats.md, "Value file"): code G MM S T,
/// label "<name> <links|rechts> <tooth>", the per-tooth values of teeth 1 (slot 1) and 18 (slot 2).
std::string value_file(const std::map<std::pair<int, int>, std::array<double, 6>>& values, const std::string& setting_179) {
  std::string t = "\xEF\xBB\xBFHEADER KS.MW.FILE\r\nTYPE       STI   ! written by the test from the documented structure\r\n";
  t += "FILTER LEAD:    F:S 2\r\n";
  t += "  22 :Zähnezahl z.......................: 35\r\n";
  t += " 178 :Vorzeichen Flankenlinie...........: LVORZ: 1: DIN\r\n";
  if (!setting_179.empty()) t += " 179 :Bezugslänge fHb...................: " + setting_179 + "\r\n";
  const std::pair<int, const char*> kinds[] = {{201, "fHa"}, {207, "ffa"}, {204, "Fa"}, {101, "fHb"}, {107, "ffb"}, {104, "Fb"}};
  for (const auto& [key, v] : values) {
    const int tooth = key.first, slot = tooth == 1 ? 1 : 2;
    const Flank side = static_cast<Flank>(key.second);
    for (std::size_t q = 0; q < 6; ++q) {
      const int code = kinds[q].first * 100 + (side == Flank::Left ? 1 : 2) * 10 + slot;
      t += fmt::format("{} : {} {} {} : {:.4f}\r\n", code, kinds[q].second, side == Flank::Left ? "links" : "rechts",
                       tooth, v[q]);
    }
  }
  return t;
}

workbench::MachineFlankComparison beside(const std::string& mew, const std::string& mka = fixture().mka) {
  const auto& wb = ideal_workbench();
  TempFile a("m.mka", mka), b("m.mew", mew);
  const auto curves = measurement::read_klingelnberg(a.path.string());
  const auto traces = measurement::klingelnberg_traces(curves, wb.setup.geometry());
  const auto iso = workbench::evaluate_iso(wb.setup.geometry(), wb.setup.ranges(), traces);
  return workbench::compare_machine_flank_values(measurement::read_klingelnberg_values(b.path.string()),
                                                 wb.setup.geometry(), wb.setup.ranges(), traces, iso.evaluation, &curves);
}

const workbench::MachineQuantitySummary& summary(const workbench::MachineFlankComparison& c, MachineQuantity q) {
  const auto it = std::find_if(c.quantities.begin(), c.quantities.end(), [&](const auto& s) { return s.quantity == q; });
  EXPECT_NE(it, c.quantities.end());
  return *it;
}

std::map<std::pair<int, int>, std::array<double, 6>> changed(std::size_t q, const std::function<double(double)>& f) {
  auto v = fixture().iso;
  for (auto& [key, row] : v) row[q] = f(row[q]);
  return v;
}

} // namespace

// Values computed from the closed forms over ISO's L_α, L_β agree with geartopo's evaluation of the export's traces.
TEST(MachineFlankValues, ClosedFormValuesAgreeWithGeartoposEvaluation) {
  const auto c = beside(value_file(fixture().iso, "BZGFL: 0: L"));
  ASSERT_EQ(c.rows.size(), 24u); // 2 teeth × 2 flanks × 6
  EXPECT_EQ(c.flagged, 0u);
  for (const auto& r : c.rows) EXPECT_NEAR(r.machine_um, r.geartopo_um, 0.01) << measurement::symbol(r.quantity) << " " << r.tooth;
  for (const auto& s : c.quantities) EXPECT_EQ(s.cause, MachineCause::None);
  EXPECT_TRUE(c.not_compared.empty());
}

// f_Hβ referred to the face width b (header line 179 BZGFL 1): every f_Hβ flagged, that reference named; nothing else.
TEST(MachineFlankValues, HelixSlopeReferredToTheFaceWidthIsNamed) {
  const double k = fixture().b_over_L_beta;
  const auto c = beside(value_file(changed(3, [&](double v) { return v * k; }), "BZGFL: 1: Z"));
  const auto& s = summary(c, MachineQuantity::HelixSlope);
  EXPECT_EQ(s.flagged, 4u);
  EXPECT_EQ(c.flagged, 4u);
  EXPECT_EQ(s.cause, MachineCause::FaceWidth);
  EXPECT_NE(s.likely_cause.find("BZGFL: 1: Z' says so"), std::string::npos) << s.likely_cause;
}

TEST(MachineFlankValues, AnOppositeSignIsNamed) {
  const auto c = beside(value_file(changed(3, [](double v) { return -v; }), ""));
  const auto& s = summary(c, MachineQuantity::HelixSlope);
  EXPECT_EQ(s.flagged, 4u);
  EXPECT_EQ(c.flagged, 4u);
  EXPECT_EQ(s.cause, MachineCause::OppositeSign);
  EXPECT_NE(s.likely_cause.find("LVORZ: 1: DIN"), std::string::npos) << s.likely_cause;
}

// Values along the flank normal (× cos β_b) while geartopo reports transverse: every quantity's cause is the direction.
TEST(MachineFlankValues, TheOtherDirectionIsNamed) {
  auto v = fixture().iso;
  for (auto& [key, row] : v)
    for (auto& x : row) x *= fixture().cos_beta_b;
  const auto c = beside(value_file(v, ""));
  EXPECT_EQ(c.flagged, 24u);
  for (const auto& s : c.quantities) EXPECT_EQ(s.cause, MachineCause::Direction) << measurement::symbol(s.quantity);
}

// The machine evaluated the whole measured trace (d_Ff … d_a, 0 … b): the measuring range is named.
TEST(MachineFlankValues, TheMeasuringRangeIsNamed) {
  const auto c = beside(value_file(fixture().measured_range, ""));
  EXPECT_GT(summary(c, MachineQuantity::HelixForm).flagged, 0u);
  EXPECT_GT(summary(c, MachineQuantity::ProfileSlope).flagged, 0u);
  for (const auto& s : c.quantities) {
    if (s.flagged == 0) continue;
    EXPECT_NE(s.likely_cause.find("the whole measured trace"), std::string::npos) << symbol(s.quantity) << ": " << s.likely_cause;
    if (s.quantity != MachineQuantity::HelixSlope) {
      EXPECT_EQ(s.cause, MachineCause::MeasuringRange) << symbol(s.quantity);
    }
  }
  // f_Hβ over 0 … b of a range centred on the face width equals f_Hβ referred to b: both are named.
  const auto& hb = summary(c, MachineQuantity::HelixSlope);
  EXPECT_EQ(hb.cause, MachineCause::FaceWidth);
  EXPECT_NE(hb.likely_cause.find("or equally"), std::string::npos) << hb.likely_cause;
}

// The machine evaluated over the export's own evaluation range (header d1 … d2, b1 … b2, off ISO's): that range is
// named for every flagged quantity.
TEST(MachineFlankValues, TheExportsEvaluationRangeIsNamed) {
  const auto c = beside(value_file(fixture().evaluation_range, ""), fixture().mka_with_evaluation_range);
  EXPECT_GE(c.flagged, 16u);
  for (const auto& s : c.quantities) {
    if (s.flagged == 0) continue;
    EXPECT_EQ(s.cause, MachineCause::EvaluationRange) << symbol(s.quantity) << ": " << s.likely_cause;
  }
  EXPECT_EQ(summary(c, MachineQuantity::HelixSlope).cause, MachineCause::EvaluationRange);
  EXPECT_EQ(summary(c, MachineQuantity::ProfileForm).cause, MachineCause::EvaluationRange);
}

// Form and total both 0.3 µm smaller, slopes equal: consistent with a filter, and said so.
TEST(MachineFlankValues, SmallerFormAndTotalWithTheSameSlopeSuggestAFilter) {
  auto v = fixture().iso;
  for (auto& [key, row] : v)
    for (const std::size_t q : {1u, 2u}) row[q] -= 0.3;
  const auto c = beside(value_file(v, ""));
  EXPECT_EQ(c.flagged, 8u);
  EXPECT_EQ(summary(c, MachineQuantity::ProfileForm).cause, MachineCause::Filter);
  EXPECT_EQ(summary(c, MachineQuantity::ProfileTotal).cause, MachineCause::Filter);
  EXPECT_NE(summary(c, MachineQuantity::ProfileForm).likely_cause.find("FILTER LEAD:    F:S 2"), std::string::npos);
  EXPECT_EQ(summary(c, MachineQuantity::ProfileSlope).cause, MachineCause::None);
}

// One value 0.3 µm off: flagged alone, and no convention is named for it.
TEST(MachineFlankValues, OneValueOffIsFlaggedAloneWithoutAFalseCause) {
  auto v = fixture().iso;
  v[{18, static_cast<int>(Flank::Right)}][0] += 0.3;
  const auto c = beside(value_file(v, ""));
  EXPECT_EQ(c.flagged, 1u);
  for (const auto& r : c.rows)
    EXPECT_EQ(r.flagged, r.tooth == 18 && r.side == Flank::Right && r.quantity == MachineQuantity::ProfileSlope);
  EXPECT_EQ(summary(c, MachineQuantity::ProfileSlope).cause, MachineCause::Unexplained);
  for (const auto& s : c.quantities)
    if (s.quantity != MachineQuantity::ProfileSlope) {
      EXPECT_EQ(s.cause, MachineCause::None);
    }
}

// A flank the export does not evaluate and a placeholder are listed, not compared.
TEST(MachineFlankValues, PlaceholdersAndFlanksWithoutTracesAreListed) {
  std::string mew = value_file(fixture().iso, "");
  mew += "20113 : fHa links 20 : 1.0000\r\n";
  const auto at = mew.find("20111 : fHa links 1 : ");
  mew.replace(at, mew.find('\r', at) - at, "20111 : fHa links 1 : -9999.0");
  const auto c = beside(mew);
  EXPECT_EQ(c.rows.size(), 23u);
  ASSERT_EQ(c.not_compared.size(), 2u);
  EXPECT_NE(c.not_compared[0].find("f_Hα tooth 1 left"), std::string::npos) << c.not_compared[0];
  EXPECT_NE(c.not_compared[0].find("placeholder"), std::string::npos);
  EXPECT_NE(c.not_compared[1].find("tooth 20"), std::string::npos) << c.not_compared[1];
}

// ------------------------------------------------------------------------------------------------ the command line


// `evaluate --traces X.mka --machine-values X.mew`: the console rows and causes are the JSON's; usage and file errors.
TEST(MachineFlankValues, EvaluatePrintsTheJsonsRowsAndRefusesWhatItCannotUse) {
  auto v = fixture().iso;
  v[{18, static_cast<int>(Flank::Right)}][0] += 0.3;
  TempFile mka("m.mka", fixture().mka), mew("m.mew", value_file(v, ""));
  TempFile mka2("n.mka", fixture().mka); // a .mew beside it (n.mew) is pointed out, not read
  std::ofstream(mka2.dir / "n.mew") << value_file(v, "");
  const auto dir = mka.dir;
  const test::CliRun r = test::run_geartopo("evaluate " + kDefaultScene + " --traces " + mka.path.string() + " --machine-values " +
                                 mew.path.string() + " --out " + (dir / "e").string(),
                             dir);
  // The default scene's machine is not ideal, but the traces are the file's: the evaluation does not depend on it.
  ASSERT_EQ(r.code, 0) << r.err;
  if (std::getenv("GEARTOPO_TEST_VERBOSE")) std::cout << r.out << r.err;
  std::ifstream in(dir / "e" / "iso1328.json");
  const auto j = nlohmann::json::parse(in)["machine_flank_values"];
  ASSERT_EQ(j["rows"].size(), 24u);
  EXPECT_EQ(j["flagged"].get<int>(), 1);
  // The console prints each JSON number to 3 decimals, a value that rounds to zero as 0.000 (never -0.000).
  const auto printed = [](const nlohmann::json& v) { return std::abs(v.get<double>()) < 5e-4 ? 0.0 : v.get<double>(); };
  for (const auto& row : j["rows"]) {
    const std::string line = fmt::format("{:9.3f} {:9.3f} {:11.3f}", printed(row["machine_um"]),
                                         printed(row["geartopo_um"]), printed(row["difference_um"]));
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  }
  EXPECT_EQ(r.out.find("-0.000 "), std::string::npos) << r.out;
  for (const auto& q : j["quantities"])
    if (q["flagged"].get<int>() > 0) {
      EXPECT_EQ(q["cause"], "unexplained");
      EXPECT_NE(r.out.find("likely cause: " + q["likely_cause"].get<std::string>()), std::string::npos) << r.out;
    }
  EXPECT_NE(r.out.find("← flagged"), std::string::npos);
  // Without the flag, a value file beside the export is named in a warning and not read.
  const test::CliRun n = test::run_geartopo("evaluate " + kDefaultScene + " --traces " + mka2.path.string() + " --out " + (dir / "n").string(), dir);
  ASSERT_EQ(n.code, 0) << n.err;
  EXPECT_NE((n.out + n.err).find("n.mew beside the export is not read"), std::string::npos) << n.out << n.err;
  EXPECT_EQ((n.out + n.err).find("The machine's values"), std::string::npos);
  // The flag without --traces is a usage error; a value file that contradicts itself is an input error naming it.
  EXPECT_EQ(test::run_geartopo("evaluate " + kDefaultScene + " --machine-values " + mew.path.string() + " --out " +
                             (dir / "u").string(),
                         dir).code,
            2);
  std::string bad = value_file(v, "");
  bad.replace(bad.find("fHa links 1 :"), 13, "fHb links 1 :");
  TempFile badmew("bad.mew", bad);
  const test::CliRun b = test::run_geartopo("evaluate " + kDefaultScene + " --traces " + mka.path.string() + " --machine-values " +
                                 badmew.path.string() + " --out " + (dir / "b").string(),
                             dir);
  EXPECT_EQ(b.code, 1);
  EXPECT_NE(b.err.find("bad.mew:"), std::string::npos) << b.err;
  EXPECT_NE(b.err.find("code and label disagree"), std::string::npos) << b.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "b" / "iso1328.json"));
}

} // namespace flank_values_test
