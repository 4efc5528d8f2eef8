// geartopo tests — the layouts a gear measuring machine delivers (named as MASTA's measured-map layouts: several
// profiles; several profiles and one lead; several leads; several leads and one profile), each read from an export
// written from the documented structure, analysed (patterns with known answers) and diagnosed (a hidden thermal drift
// found). Units: mm, µm.
#include "../trace_export_fixture.hpp"

#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/measurement/any_measurement.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

using namespace geartopo;
using namespace trace_fixture;

namespace {

enum class Kind { Profiles, ProfilesAndOneLead, Leads, LeadsAndOneProfile };

const char* name(Kind k) {
  switch (k) {
  case Kind::Profiles: return "several profiles";
  case Kind::ProfilesAndOneLead: return "several profiles and one lead";
  case Kind::Leads: return "several leads";
  case Kind::LeadsAndOneProfile: return "several leads and one profile";
  }
  return "?";
}

Layout layout(Kind k) {
  const auto& g = ideal_workbench().setup.geometry();
  const double xa = g.roll_length_at(g.root_form_diameter_mm()), xe = g.roll_length_at(g.tip_diameter_mm());
  const auto d_at = [&](double f) { return g.diameter_at_roll_length(xa + f * (xe - xa)); };
  Layout l;
  l.profile_points = 150, l.helix_points = 200;
  switch (k) {
  case Kind::Profiles: l.profile_z_mm = {15.0, 45.0, 75.0, 105.0, 135.0}; break;
  case Kind::ProfilesAndOneLead: l.profile_z_mm = {20.0, 75.0, 130.0}, l.helix_d_mm = {d_at(0.55)}; break;
  case Kind::Leads: l.helix_d_mm = {d_at(0.2), d_at(0.4), d_at(0.6), d_at(0.8)}; break;
  case Kind::LeadsAndOneProfile: l.helix_d_mm = {d_at(0.25), d_at(0.5), d_at(0.75)}, l.profile_z_mm = {75.0}; break;
  }
  return l;
}

std::vector<measurement::MeasuredPoint> read(const Export& e, const grinding::GrindingSetup& setup) {
  TempFile f("layout.mka", e.text);
  return measurement::read_any_measurement(f.path.string(), setup);
}

class TraceLayout : public ::testing::TestWithParam<Kind> {};

} // namespace

// Analysed: offset, slopes, crownings as written (to 0.05 µm) with 0.1 µm noise; waviness scanned only along the
// directions with measured lines, and a wave there found (1 µm, 9 mm along the profile; 1 µm, 30 mm along z).
TEST_P(TraceLayout, IsReadAndAnalysed) {
  const Kind k = GetParam();
  SCOPED_TRACE(name(k));
  const auto& wb = ideal_workbench();
  const auto& r = wb.setup.ranges();
  const double x0 = r.xi_eval_start_mm, x1 = r.xi_eval_end_mm, z0 = r.z_eval_start_mm, z1 = r.z_eval_end_mm;
  const double a = -1.0, s_a = 2.0, s_b = 1.5, C_a = 3.0, C_b = 2.0, A = 1.0, lambda_p = 9.0, lambda_h = 30.0;
  const Layout l = layout(k);
  const bool profiles = !l.profile_z_mm.empty(), leads = !l.helix_d_mm.empty();
  std::mt19937_64 gen(11);
  std::normal_distribution<double> noise(0.0, 0.1);
  const auto truth = [&](Flank, int, double xi, double z) {
    const double u = 2 * (xi - x0) / (x1 - x0) - 1, w = 2 * (z - z0) / (z1 - z0) - 1;
    double v = a + s_a / 2 * u + s_b / 2 * w + C_a * (1.0 / 3 - u * u) + C_b * (1.0 / 3 - w * w) + noise(gen);
    // A wave only along a direction with measured lines: a few lines across it cannot sample it.
    if (profiles) v += A * std::sin(2 * std::numbers::pi * xi / lambda_p);
    if (leads) v += A * std::sin(2 * std::numbers::pi * z / lambda_h);
    return v;
  };
  const auto pts = read(write_export(wb.setup.geometry(), l, truth), wb.setup);
  const auto c = diagnosis::compare(wb.setup, wb.process(), pts, 0.0);
  EXPECT_NEAR(c.noise_um, 0.1, 0.015);
  ASSERT_EQ(c.flanks.size(), 4u);
  for (std::size_t f = 0; f < c.flanks.size(); ++f) {
    ASSERT_TRUE(c.has_patterns[f]);
    const auto& p = c.patterns[f];
    SCOPED_TRACE(diagnosis::describe_patterns(p));
    EXPECT_NEAR(p.offset_um.value, a, 0.05);
    EXPECT_NEAR(p.profile_slope_um.value, s_a, 0.05);
    EXPECT_NEAR(p.helix_slope_um.value, s_b, 0.05);
    EXPECT_NEAR(p.profile_crowning_um.value, C_a, 0.05);
    EXPECT_NEAR(p.helix_crowning_um.value, C_b, 0.05);
    EXPECT_EQ(p.waviness_profile.scanned, profiles);
    EXPECT_EQ(p.waviness_helix.scanned, leads);
    if (profiles) {
      ASSERT_TRUE(p.waviness_profile.wave.has_value());
      EXPECT_NEAR(p.waviness_profile.wave->amplitude_um.value, A, 0.05);
      EXPECT_NEAR(p.waviness_profile.wave->wavelength_mm, lambda_p, 0.01 * lambda_p);
    }
    if (leads) {
      ASSERT_TRUE(p.waviness_helix.wave.has_value());
      EXPECT_NEAR(p.waviness_helix.wave->amplitude_um.value, A, 0.05);
      EXPECT_NEAR(p.waviness_helix.wave->wavelength_mm, lambda_h, 0.01 * lambda_h);
    }
  }
}

// Diagnosed: the default scene's gear with the thermal drift of scenes/truth-skmc1200w-mn14-z35.yaml (x growth 9 µm,
// time constant 600 s), not in the model, measured in the layout on teeth 1 and 18 with 0.3 µm noise: diagnose
// (noise estimated from the lines) names the thermal drift.
TEST_P(TraceLayout, IsDiagnosed) {
  const Kind k = GetParam();
  SCOPED_TRACE(name(k));
  const workbench::Workbench model{std::filesystem::path(kDefaultScene)};
  const workbench::Workbench truth{std::filesystem::path(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml")};
  const Layout l = layout(k);
  // Positions first (an export of zeros), then the truth's deviations there, written in file order.
  const auto at = read(write_export(model.setup.geometry(), l, [](Flank, int, double, double) { return 0.0; }), model.setup);
  const auto values = diagnosis::predict(truth.setup, truth.process(), at, grinding::Method::Exact);
  std::mt19937_64 gen(5);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::size_t next = 0;
  const auto pts = read(write_export(model.setup.geometry(), l, [&](Flank, int, double, double) { return values[next++] + noise(gen); }),
                        model.setup);
  ASSERT_EQ(next, pts.size());
  diagnosis::DiagnoseOptions o;
  const auto d = diagnosis::diagnose(model.setup, model.process(), pts, {}, o);
  EXPECT_NEAR(d.noise_um, 0.3, 0.03);
  ASSERT_TRUE(d.chosen.has_value()) << d.verdict;
  EXPECT_EQ(d.chosen->name(), "thermal_drift") << d.verdict;
}

INSTANTIATE_TEST_SUITE_P(Layouts, TraceLayout,
                         ::testing::Values(Kind::Profiles, Kind::ProfilesAndOneLead, Kind::Leads, Kind::LeadsAndOneProfile),
                         [](const auto& info) {
                           switch (info.param) {
                           case Kind::Profiles: return std::string("SeveralProfiles");
                           case Kind::ProfilesAndOneLead: return std::string("SeveralProfilesAndOneLead");
                           case Kind::Leads: return std::string("SeveralLeads");
                           case Kind::LeadsAndOneProfile: return std::string("SeveralLeadsAndOneProfile");
                           }
                           return std::string("Unknown");
                         });

// The same hidden thermal drift measured as the 7 × 9 grid (topology rows of teeth 1 and 18) and as traces (three
// profile and two helix lines per flank, an export) with the same 0.3 µm noise: diagnose names the same effect, and
// the fitted thickness set-up term agrees within 3 combined standard errors.
TEST(TraceDiagnosis, SameThermalDriftAsGridAndAsTracesGivesTheSameDiagnosis) {
  const workbench::Workbench model{std::filesystem::path(kDefaultScene)};
  const workbench::Workbench truth{std::filesystem::path(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml")};
  std::mt19937_64 gen(31);
  std::normal_distribution<double> noise(0.0, 0.3);
  // Grid: the truth's topology at the scene's grid, as a topology CSV would hold it.
  grinding::SimulationOptions so;
  so.teeth = {1, 18};
  auto rows = grinding::topology_rows(grinding::simulate_topology(truth.setup, truth.process(), so));
  for (auto& r : rows) r.deviation_um += noise(gen);
  const auto grid = measurement::measured_points(rows, model.setup.geometry(), "grid");
  // Traces: the truth's deviations at the points of an export of three profile and two helix lines per flank.
  const auto& g = model.setup.geometry();
  Layout l;
  l.profile_z_mm = {20.0, 75.0, 130.0};
  const double xa = g.roll_length_at(g.root_form_diameter_mm()), xe = g.roll_length_at(g.tip_diameter_mm());
  l.helix_d_mm = {g.diameter_at_roll_length(xa + 0.4 * (xe - xa)), g.diameter_at_roll_length(xa + 0.7 * (xe - xa))};
  const auto at = read(write_export(g, l, [](Flank, int, double, double) { return 0.0; }), model.setup);
  const auto values = diagnosis::predict(truth.setup, truth.process(), at, grinding::Method::Exact);
  std::size_t next = 0;
  const auto traces = read(write_export(g, l, [&](Flank, int, double, double) { return values[next++] + noise(gen); }), model.setup);

  const diagnosis::DiagnoseOptions o; // noise estimated: the grid's surface, the traces' lines
  const auto d_grid = diagnosis::diagnose(model.setup, model.process(), grid, {}, o);
  const auto d_traces = diagnosis::diagnose(model.setup, model.process(), traces, {}, o);
  ASSERT_TRUE(d_grid.chosen.has_value()) << d_grid.verdict;
  ASSERT_TRUE(d_traces.chosen.has_value()) << d_traces.verdict;
  EXPECT_EQ(d_grid.chosen->name(), "thermal_drift") << d_grid.verdict;
  EXPECT_EQ(d_traces.chosen->name(), d_grid.chosen->name()) << d_traces.verdict;
  EXPECT_NEAR(d_grid.noise_um, 0.3, 0.05);
  EXPECT_NEAR(d_traces.noise_um, 0.3, 0.03);
  EXPECT_NEAR(d_traces.setup.thickness_um, d_grid.setup.thickness_um,
              3 * std::hypot(d_traces.setup.thickness_sd_um, d_grid.setup.thickness_sd_um));
}

// A large measurement's fits search from their starts on every k-th point, then refine the best start on all points
// (DiagnoseOptions::fit_search_points). The truth scene's thermal drift (x growth 9 µm, z growth 0, time constant
// 600 s: scenes/truth-skmc1200w-mn14-z35.yaml) measured on four teeth spread round the gear, three profile and three
// helix lines of 300 points per flank (14 400 points, 0.3 µm noise): searched on every 8th point, every candidate
// (single effects and pairs) comes out as searched on all points — each fitted value within 1 % of its standard
// uncertainty (and every µm value within 0.01 µm), ΔBIC within 0.01 — and the thermal drift is the truth's within 3σ.
TEST(TraceDiagnosis, FitSearchOnASubsampleGivesTheFitOnAllPoints) {
  const workbench::Workbench model{std::filesystem::path(kDefaultScene)};
  const workbench::Workbench truth{std::filesystem::path(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml")};
  const auto& g = model.setup.geometry();
  Layout l;
  l.teeth = {1, 9, 18, 27};
  l.profile_z_mm = {20.0, 75.0, 130.0};
  const double xa = g.roll_length_at(g.root_form_diameter_mm()), xe = g.roll_length_at(g.tip_diameter_mm());
  for (const double f : {0.3, 0.5, 0.7}) l.helix_d_mm.push_back(g.diameter_at_roll_length(xa + f * (xe - xa)));
  l.profile_points = l.helix_points = 300;
  const auto at = read(write_export(g, l, [](Flank, int, double, double) { return 0.0; }), model.setup);
  const auto values = diagnosis::predict(truth.setup, truth.process(), at, grinding::Method::Exact);
  std::mt19937_64 gen(17);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::size_t next = 0;
  const auto pts = read(write_export(g, l, [&](Flank, int, double, double) { return values[next++] + noise(gen); }), model.setup);
  ASSERT_EQ(pts.size(), 14400u);

  diagnosis::DiagnoseOptions all, sub;
  all.fit_search_points = 0;
  sub.fit_search_points = 2000; // stride 8
  const auto d_all = diagnosis::diagnose(model.setup, model.process(), pts, {}, all);
  const auto d_sub = diagnosis::diagnose(model.setup, model.process(), pts, {}, sub);
  ASSERT_TRUE(d_all.chosen.has_value()) << d_all.verdict;
  ASSERT_TRUE(d_sub.chosen.has_value()) << d_sub.verdict;
  EXPECT_EQ(d_sub.chosen->name(), d_all.chosen->name());
  EXPECT_EQ(d_sub.rivals.size(), d_all.rivals.size());

  std::vector<diagnosis::Candidate> fits_all = d_all.ranked, fits_sub = d_sub.ranked;
  if (d_all.combination) fits_all.push_back(*d_all.combination);
  if (d_sub.combination) fits_sub.push_back(*d_sub.combination);
  ASSERT_EQ(fits_sub.size(), fits_all.size());
  for (const auto& a : fits_all) {
    SCOPED_TRACE(a.name());
    const auto s = std::find_if(fits_sub.begin(), fits_sub.end(), [&](const auto& c) { return c.name() == a.name(); });
    ASSERT_NE(s, fits_sub.end());
    EXPECT_NEAR(s->delta_bic, a.delta_bic, 0.01);
    for (std::size_t e = 0; e < a.parameters.size(); ++e)
      for (std::size_t k = 0; k < a.parameters[e].size(); ++k) {
        const auto &pa = a.parameters[e][k], &ps = s->parameters[e][k];
        SCOPED_TRACE(pa.key);
        const bool um = pa.key.ends_with("_um");
        EXPECT_NEAR(ps.value, pa.value, um ? std::min(0.01, 0.01 * pa.uncertainty) : 0.01 * pa.uncertainty);
        EXPECT_NEAR(ps.uncertainty, pa.uncertainty, 0.01 * pa.uncertainty);
      }
  }
  // Against the truth (outside the fit): the subsample-searched thermal drift.
  const auto thermal = std::find_if(d_sub.ranked.begin(), d_sub.ranked.end(), [](const auto& c) { return c.name() == "thermal_drift"; });
  ASSERT_NE(thermal, d_sub.ranked.end());
  const auto& p = thermal->parameters.front(); // x_growth_um, z_growth_um, time_constant_s
  EXPECT_NEAR(p[0].value, 9.0, 3 * p[0].uncertainty);
  EXPECT_NEAR(p[1].value, 0.0, 3 * p[1].uncertainty);
  EXPECT_NEAR(p[2].value, 600.0, 3 * p[2].uncertainty);
}
