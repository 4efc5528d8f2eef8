// Measured traces (traces CSV) in compare and diagnose, and the model's nominal flank at the mean tooth-thickness
// allowance (docs/measurement-formats.md, docs/conventions.md). The expected residuals are written here: the "measured"
// traces are the simulator's traces (grinding::simulate_topology, not the point-wise prediction compare uses) plus a
// known function; the allowance offset is checked against W_k, M_dK and the transverse base thickness computed here.
// Units: mm, µm, rad.
#include "geartopo/core/input_error.hpp"
#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <numbers>
#include <sstream>

using namespace geartopo;

namespace {

const std::string kTracesDefaultScene = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";

std::string traces_scene_text(const std::string& extra_gear_keys) {
  std::ifstream in(kTracesDefaultScene);
  std::stringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  const std::string anchor = "gear:\n";
  text.insert(text.find(anchor) + anchor.size(), extra_gear_keys);
  return text;
}

const workbench::Workbench& traces_model() {
  static const workbench::Workbench b(kTracesDefaultScene);
  return b;
}

/// The simulator's profile and helix traces of teeth 1 and 18 (both flanks) of the default scene.
const std::vector<grinding::FlankTopology>& simulated_traces() {
  static const std::vector<grinding::FlankTopology> t = [] {
    grinding::SimulationOptions o;
    o.teeth = {1, 18};
    o.profile_points = 25;
    o.helix_points = 30;
    return grinding::simulate_topology(traces_model().setup, traces_model().process(), o);
  }();
  return t;
}

/// A file in a fresh temporary folder (removed with the object).
struct TracesTempFile {
  std::filesystem::path dir, path;
  explicit TracesTempFile(const std::string& name) {
    dir = std::filesystem::temp_directory_path() /
          ("geartopo_traces_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir);
    path = dir / name;
  }
  ~TracesTempFile() { std::filesystem::remove_all(dir); }
};

/// The simulated traces with f(ξ, z) (µm) added to every point.
std::vector<grinding::FlankTopology> traces_plus(const std::function<double(double, double)>& f) {
  auto t = simulated_traces();
  for (auto& ft : t)
    for (auto* trace : {&ft.profile, &ft.helix})
      for (auto& p : *trace) p.deviation_um += f(p.roll_length_mm, p.z_mm);
  return t;
}

std::size_t traces_point_count(const std::vector<grinding::FlankTopology>& t) {
  std::size_t n = 0;
  for (const auto& ft : t) n += ft.profile.size() + ft.helix.size();
  return n;
}

} // namespace

// A traces CSV is told apart by its header and compared point by point: the model is evaluated at each trace point,
// so the residual is exactly what was added to the model's traces.
TEST(MeasuredTraces, TracesCsvComparesLikeATopologyCsv) {
  const auto added = [](double xi, double z) { return 2.0 + 0.03 * (xi - 100.0) - 0.01 * (z - 75.0); };
  const auto measured = traces_plus(added);
  TracesTempFile file("measured_traces.csv");
  grinding::write_traces_csv(file.path, measured);

  std::vector<std::string> warnings;
  const auto pts = measurement::read_any_measurement(file.path.string(), traces_model().setup, &warnings);
  ASSERT_EQ(pts.size(), traces_point_count(measured));
  EXPECT_TRUE(warnings.empty());
  const auto c = diagnosis::compare(traces_model().setup, traces_model().process(), pts, 0.5);
  ASSERT_EQ(c.residual_um.size(), pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_EQ(pts[i].row, 0);
    EXPECT_EQ(pts[i].col, 0);
    EXPECT_GT(pts[i].line, 1); // the header is line 1
    // The file rounds positions and deviations (6 and 4 decimals): 1e-3 µm covers it.
    ASSERT_NEAR(c.residual_um[i], added(pts[i].roll_length_mm, pts[i].z_mm), 1e-3) << "point " << i;
  }
  EXPECT_EQ(c.flanks.size(), 4u); // teeth 1 and 18, both flanks
  EXPECT_DOUBLE_EQ(c.allowance_offset_um, 0.0);
}

// A trace point off the flank is an error naming the file, its line and the field.
TEST(MeasuredTraces, TracePointOffTheFlankNamesItsLine) {
  auto measured = simulated_traces();
  const auto& g = traces_model().setup.geometry();
  auto& bad = measured[1].profile.back(); // the last profile point of tooth 1 right: still increasing roll length
  bad.diameter_mm = g.tip_diameter_mm() + 1.0;
  bad.roll_length_mm = g.roll_length_at(bad.diameter_mm);
  TracesTempFile file("off_flank.csv");
  grinding::write_traces_csv(file.path, measured);
  // The bad point is the last profile point of the second flank: line = header + the first flank's points + 25.
  const int line = 1 + static_cast<int>(measured[0].profile.size() + measured[0].helix.size()) + 25;
  try {
    measurement::read_any_measurement(file.path.string(), traces_model().setup);
    FAIL() << "an off-flank trace point was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.path.string() + ":" + std::to_string(line) + ":"), std::string::npos) << what;
    EXPECT_NE(what.find("diameter_mm"), std::string::npos) << what;
  }
}

// diagnose takes traces too: the model plus a uniform thickness offset is a set-up term, no effect is named.
TEST(MeasuredTraces, TracesCsvGoesThroughDiagnose) {
  const double offset_um = -3.0;
  const auto measured = traces_plus([&](double, double) { return offset_um; });
  TracesTempFile file("diagnose_traces.csv");
  grinding::write_traces_csv(file.path, measured);
  const auto pts = measurement::read_any_measurement(file.path.string(), traces_model().setup);
  diagnosis::DiagnoseOptions o;
  o.noise_um = 0.5;
  o.candidates = {"thermal_drift"};
  const auto d = diagnosis::diagnose(traces_model().setup, traces_model().process(), pts, {}, o);
  EXPECT_EQ(d.points, static_cast<int>(pts.size()));
  EXPECT_NEAR(d.setup.thickness_um, offset_um, 0.01);
  EXPECT_FALSE(d.chosen.has_value());
}

// The allowance offset Δn = (A_sne + A_sni)/2 · cos α_n / 2 per flank, checked three independent ways:
// (1) W_k is the normal distance of two flanks: ΔW_k = 2 Δn;
// (2) the transverse base-circle thickness s_bt = d_b (s_t/d + inv α_t) changes by (d_b/d) A_sn / cos β, i.e. each
//     flank moves (d_b/d) A_sn / (2 cos β) along the base tangent in the transverse plane, × cos β_b along its normal;
// (3) M_dK: both flanks of a space moving by Δn push a ball out radially by Δn / (cos β_b sin α_Mt) (the runout
//     geometry of docs/iso1328.md), so ΔM_dK = 2 Δn / (cos β_b sin α_Mt) · cos(90°/z) for odd z.
TEST(AllowanceOffset, EqualsTheFlankDisplacementSeenByWkMdKAndTheBaseThickness) {
  const double upper_um = -40.0, lower_um = -80.0, mean_mm = 1e-3 * (upper_um + lower_um) / 2;
  const workbench::Workbench wb(scene::parse_scene(
      traces_scene_text("  thickness_allowance_upper_um: -40\n  thickness_allowance_lower_um: -80\n"), kTracesDefaultScene));
  const auto& g = wb.setup.geometry();
  const double dn_um = diagnosis::mean_allowance_offset_um(g);
  EXPECT_NEAR(dn_um, 1e3 * mean_mm * std::cos(20.0 * std::numbers::pi / 180) / 2, 1e-9); // −28.19 µm

  const int k = g.span_teeth();
  EXPECT_NEAR(1e3 * (g.base_tangent_length_mm(k, mean_mm) - g.base_tangent_length_mm(k)), 2 * dn_um, 1e-9);

  const double alpha_n = 20.0 * std::numbers::pi / 180, beta = 30.0 * std::numbers::pi / 180;
  const double alpha_t = std::atan(std::tan(alpha_n) / std::cos(beta));
  const double beta_b = std::asin(std::sin(beta) * std::cos(alpha_n));
  const double transverse_um = 1e3 * std::cos(alpha_t) * mean_mm / (2 * std::cos(beta)); // d_b / d = cos α_t
  EXPECT_NEAR(transverse_um * std::cos(beta_b), dn_um, 1e-9);

  const double ball = g.ball_diameter_mm();
  const double dM_um = 1e3 * (g.dimension_over_balls_mm(ball, mean_mm) - g.dimension_over_balls_mm(ball));
  const double alpha_Mt = std::acos(g.base_diameter_mm() / g.ball_centre_diameter_mm(ball));
  const int z = 35;
  const double expected_dM_um = 2 * dn_um / (std::cos(beta_b) * std::sin(alpha_Mt)) * std::cos(std::numbers::pi / (2 * z));
  EXPECT_NEAR(dM_um, expected_dM_um, 0.01 * std::abs(expected_dM_um)); // first order in A_sn: 1 % is the 2nd order
}

// With allowances in the scene, a gear ground to the mean allowance compares without a constant offset; without them
// in the scene, the same gear shows Δn on every flank.
TEST(AllowanceOffset, GearGroundToTheMeanAllowanceComparesWithoutOffset) {
  const double alpha_n = 20.0 * std::numbers::pi / 180;
  const double dn_um = -60.0 * std::cos(alpha_n) / 2; // mean of −40 and −80 µm
  const auto measured = traces_plus([&](double, double) { return dn_um; });
  TracesTempFile file("ground_to_allowance.csv");
  grinding::write_traces_csv(file.path, measured);

  const workbench::Workbench with(scene::parse_scene(
      traces_scene_text("  thickness_allowance_upper_um: -40\n  thickness_allowance_lower_um: -80\n"), kTracesDefaultScene));
  const auto pts = measurement::read_any_measurement(file.path.string(), with.setup);
  const auto c_with = diagnosis::compare(with.setup, with.process(), pts, 0.5);
  const auto c_without = diagnosis::compare(traces_model().setup, traces_model().process(), pts, 0.5);
  EXPECT_NEAR(c_with.allowance_offset_um, dn_um, 1e-9);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    ASSERT_NEAR(c_with.residual_um[i], 0.0, 1e-3) << "point " << i;
    ASSERT_NEAR(c_without.residual_um[i], dn_um, 1e-3) << "point " << i;
  }
}

// A Klingelnberg export's profile and helix traces go into the ISO 1328-1 evaluator (geartopo evaluate --traces).
// The file is written here in the export's raw convention (transverse values; profile left × −1, helix × −1 give the DIN
// sign) for a helix angle larger than designed by Δβ on both flanks of tooth 1, and a profile gaining 5 µm
// (transverse, DIN sign) from root to tip. Expected, transverse: f_Hβ = +L_β (d_b/d) |Δ tan β| on both flanks (the
// helix-angle sign rule, docs/iso1328.md), f_Hα = +5 µm × L_α / (ξ_e − ξ_a) on both flanks.
TEST(MeasuredTraces, KlingelnbergExportTracesAreEvaluatedToIso) {
  const auto& wb = traces_model();
  const auto& g = wb.setup.geometry();
  const double b = g.spec().face_width_mm, beta = g.spec().helix_angle_rad, dbeta = 1e-4;
  const double da = g.root_form_diameter_mm(), de = g.tip_diameter_mm(); // the measuring range covers L_α
  const double xa = g.roll_length_at(da), xe = g.roll_length_at(de);
  const double d = g.reference_diameter_mm(), db = g.base_diameter_mm();
  const double d_helix = g.diameter_at_roll_length(0.5 * (xa + xe));
  const int n = 60;
  std::string text = "HEADER KS.MK.FILE\n";
  text += "  21 :Normalmodul mn [mm]...............: 14.0000\n  22 :Zähnezahl z.......................: 35\n";
  text += fmt::format("  41 :Start Messbereich.....da [mm].....: {:.6f} {:.6f}\n", da, da);
  text += fmt::format("  44 :Ende der Messstrecke..de [mm].....: {:.6f} {:.6f}\n", de, de);
  text += fmt::format("  61 :Messanfang............ba [mm].....: {:.6f} {:.6f}\n", 0.0, 0.0);
  text += fmt::format("  64 :Messende..............be [mm].....: {:.6f} {:.6f}\n", b, b);
  for (const char* side : {"links", "rechts"}) {
    const double sigma = std::string(side) == "rechts" ? 1.0 : -1.0;
    text += fmt::format("Profil:  Zahn-Nr.: 1 {} / {} Werte / z= {:.4f}\n", side, n, 0.5 * b);
    for (int i = 0; i < n; ++i) // DIN sign: +5 µm · u; raw: × (−1 left, +1 right)
      text += fmt::format(" {:.5f}{}", (sigma > 0 ? 1.0 : -1.0) * 5.0 * i / (n - 1), i + 1 == n ? "\n" : "");
    text += fmt::format("Flankenlinie: Zahn-Nr.: 1 {} / {} Werte / d= {:.6f}\n", side, n, d_helix);
    for (int i = 0; i < n; ++i) {
      // Transverse value of a helix angle β + Δβ (right hand): σ r_b (2/d) Δ tan β (z − b/2); raw helix sign × −1.
      const double z = b * i / (n - 1);
      const double transverse_um = 1e3 * sigma * (db / 2) * (2 / d) * (std::tan(beta + dbeta) - std::tan(beta)) * (z - b / 2);
      text += fmt::format(" {:.5f}{}", -transverse_um, i + 1 == n ? "\n" : "");
    }
  }
  TracesTempFile file("export.mka");
  { std::ofstream(file.path) << text; }
  std::vector<std::string> warnings;
  const auto traces = measurement::klingelnberg_traces(measurement::read_klingelnberg(file.path.string()), g, {}, &warnings);
  ASSERT_EQ(traces.size(), 2u);
  const auto iso = workbench::evaluate_iso(g, wb.setup.ranges(), traces);
  const auto& r = wb.setup.ranges();
  const double f_Hb = (r.z_eval_end_mm - r.z_eval_start_mm) * (db / d) * 1e3 * (std::tan(beta + dbeta) - std::tan(beta));
  const double f_Ha = 5.0 * (r.xi_eval_end_mm - r.xi_eval_start_mm) / (xe - xa);
  ASSERT_EQ(iso.evaluation.flanks.size(), 2u);
  for (const auto& f : iso.evaluation.flanks) {
    SCOPED_TRACE(geartopo::to_string(f.side));
    // The file's 5 decimals and the reader's × cos β_b then / cos β_b: 1e-4 µm.
    EXPECT_NEAR(f.helix.slope_um, f_Hb, 1e-3);
    EXPECT_NEAR(f.profile.slope_um, f_Ha, 1e-3);
  }
  EXPECT_GT(f_Hb, 1.0); // a visible value, not a vacuous check
}

// A Klingelnberg export goes through compare and diagnose like a topology CSV: the model's grid of teeth 1 and 18,
// plus a known offset, written as an export (TOPOGRAFIE profile lines) and read back by content: the residual is the
// offset at every point (the export's 3 decimals of transverse values: 1e-3 µm), and diagnose takes it as the set-up
// thickness term, naming no effect.
TEST(MeasuredTraces, KlingelnbergExportGoesThroughCompareAndDiagnose) {
  const auto& wb = traces_model();
  grinding::SimulationOptions so;
  so.teeth = {1, 18};
  auto rows = grinding::topology_rows(grinding::simulate_topology(wb.setup, wb.process(), so));
  const double offset_um = 1.5;
  for (auto& r : rows) r.deviation_um += offset_um;
  TracesTempFile file("grid.mka");
  {
    std::ofstream out(file.path);
    measurement::write_klingelnberg(out, wb.setup.geometry(), rows);
  }
  std::vector<std::string> warnings;
  const auto pts = measurement::read_any_measurement(file.path.string(), wb.setup, &warnings);
  ASSERT_EQ(pts.size(), rows.size());
  EXPECT_TRUE(warnings.empty());
  const auto c = diagnosis::compare(wb.setup, wb.process(), pts, 0.5);
  for (std::size_t i = 0; i < pts.size(); ++i) ASSERT_NEAR(c.residual_um[i], offset_um, 1e-3) << "point " << i;
  EXPECT_EQ(c.flanks.size(), 4u);

  diagnosis::DiagnoseOptions o;
  o.noise_um = 0.5;
  o.candidates = {"thermal_drift"};
  const auto d = diagnosis::diagnose(wb.setup, wb.process(), pts, {}, o);
  EXPECT_NEAR(d.setup.thickness_um, offset_um, 0.01);
  EXPECT_FALSE(d.chosen.has_value());
}
