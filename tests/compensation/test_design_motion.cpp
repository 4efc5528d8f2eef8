// The axis motions that grind a designed helix crowning (compensation/design_motion.hpp), on an ideal machine.
// Truths from outside the grinder:
//  - radial infeed: the ground flank (exact envelope) equals the first-order field of the X offset ΔX(Z_gen) at each
//    point's generating stroke position, written here from the documented chain (machine::ideal_wMg of the command with
//    and without ΔX, applied to the point, along its normal) — and so carries the twist that field has;
//  - twist free: the ground flank is the design to within 20 % of the radial infeed's twist (issue 26);
//  - on the CAFXZY (issue 42) the motions are its own axes: its X slide is the centre distance (X = x, the closed form
//    of docs/machine-model.md §9), so radial infeed moves X alone by the CFXZAY's Δx; ground through the CAFXZY's
//    chain (ChainProcess, its own forward kinematics) both modes give the flanks they give on the CFXZAY.
#include "../gears/gear_fixtures.hpp"
#include "geartopo/compensation/design_motion.hpp"
#include "geartopo/evaluation/crowning.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/grinding/chain_process.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/machine_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <cstdio>

using namespace geartopo;

namespace {

constexpr double kCrowningUm = 6.0;

grinding::GrindingSetup crowned_paper_gear() {
  gears::GearSpec spec = test::paper_gear();
  gears::FlankModifications m;
  m.helix_crowning_um = kCrowningUm;
  spec.modifications = {m, m, {}};
  return grinding::GrindingSetup(spec, {350.0, 0.0}, {});
}

const grinding::GrindingSetup& setup() {
  static const grinding::GrindingSetup s = crowned_paper_gear();
  return s;
}

compensation::CorrectionTable motions(grinding::LeadCrowning mode) {
  const machine::MachineModel model(machine::Strokes::skmc_1200w(), {});
  return compensation::design_motions(setup(), mode, {model, 300.0});
}

struct Grid {
  std::vector<double> xi, z;
};
Grid grid() {
  const auto& r = setup().ranges();
  Grid g;
  for (int i = 0; i < 7; ++i) g.xi.push_back(r.xi_eval_start_mm + r.profile_evaluation_length() * i / 6.0);
  for (int j = 0; j < 9; ++j) g.z.push_back(r.z_eval_start_mm + r.helix_evaluation_length() * j / 8.0);
  return g;
}

/// Least-squares slope × range (µm over the range): the slope deviation of a line of values, as f_Hα / f_Hβ.
double slope_over_range(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= static_cast<double>(x.size()), my /= static_cast<double>(y.size());
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
  return sxy / sxx * (x.back() - x.front());
}

/// Profile twist S_α: the profile slope at the last column of L_β less the one at the first (µm), from a 7×9 field.
double profile_twist_um(const Grid& g, const std::vector<std::vector<double>>& field) {
  std::vector<double> first, last;
  for (size_t i = 0; i < g.xi.size(); ++i) first.push_back(field[i].front()), last.push_back(field[i].back());
  return slope_over_range(g.xi, last) - slope_over_range(g.xi, first);
}

} // namespace

TEST(DesignMotion, RadialInfeedGrindsTheFirstOrderFieldOfItsXOffsetAndItsTwist) {
  const auto table = motions(grinding::LeadCrowning::RadialInfeed);
  for (const auto& row : table.rows()) ASSERT_EQ(row.correction.tail<4>().norm(), 0.0) << "X alone moves";
  const grinding::IdealProcess ideal;
  const compensation::CompensatedProcess process(ideal, table); // holds references: both named
  const auto& s = setup();
  const grinding::FlankDeviation dev(s.flanks(), s.wheel(), s.path(), process);
  const grinding::FlankDeviation nominal(s.flanks(), s.wheel(), s.path(), ideal);
  const Grid g = grid();
  double worst = 0.0, largest_field = 0.0;
  for (auto flank : {Flank::Left, Flank::Right}) {
    std::vector<std::vector<double>> ground(g.xi.size(), std::vector<double>(g.z.size()));
    auto field = ground;
    for (size_t i = 0; i < g.xi.size(); ++i)
      for (size_t j = 0; j < g.z.size(); ++j) {
        const auto t = dev.target(3, flank, g.xi[i], g.z[j]);
        ground[i][j] = 1e3 * (dev.at(t, grinding::Method::Exact).deviation_mm + t.design_mm);
        // The generating pose of the point on the ideal machine, and the chain with and without the table's ΔX there.
        const double z_gen = nominal.at(t, grinding::Method::Exact).z_stroke_mm;
        const grinding::PathPoint pp = s.path().point(t.space, z_gen);
        machine::AxisPose moved = pp.q;
        moved.x += table.at(t.space, z_gen)(0);
        const machine::Pose shift = machine::ideal_wMg(moved) * machine::ideal_wMg(pp.q).inverse();
        field[i][j] = 1e3 * t.fp.n.dot(shift * t.fp.p - t.fp.p);
        worst = std::max(worst, std::abs(ground[i][j] - field[i][j]));
        largest_field = std::max(largest_field, std::abs(field[i][j]));
      }
    const double s_ground = profile_twist_um(g, ground), s_field = profile_twist_um(g, field);
    std::printf("%s flank: profile twist S_alpha ground %.3f um, first-order field %.3f um\n", std::string(to_string(flank)).c_str(),
                s_ground, s_field);
    EXPECT_NEAR(s_ground, s_field, 0.05);
    EXPECT_GT(std::abs(s_field), 1.0) << "a 6 µm crowning by radial infeed twists this helical flank by µm";
  }
  std::printf("radial infeed: largest |ground - field| %.4f um, largest field %.3f um\n", worst, largest_field);
  EXPECT_LT(worst, 0.05);
  EXPECT_GT(largest_field, 0.5 * kCrowningUm);
}

TEST(DesignMotion, TwistFreeMotionsLeaveLessThanAFifthOfTheRadialInfeedsTwist) {
  const auto& s = setup();
  const Grid g = grid();
  const auto largest_from_design_um = [&](const compensation::CorrectionTable& table) {
    const grinding::IdealProcess ideal;
    const compensation::CompensatedProcess process(ideal, table);
    const grinding::FlankDeviation dev(s.flanks(), s.wheel(), s.path(), process);
    double worst = 0.0;
    for (auto flank : {Flank::Left, Flank::Right})
      for (double xi : g.xi)
        for (double z : g.z) worst = std::max(worst, std::abs(1e3 * dev.at(3, flank, xi, z, grinding::Method::Exact).deviation_mm));
    return worst;
  };
  const double infeed = largest_from_design_um(motions(grinding::LeadCrowning::RadialInfeed));
  const double twist_free = largest_from_design_um(motions(grinding::LeadCrowning::TwistFree));
  std::printf("largest |deviation from the design|: radial infeed %.3f um, twist free %.3f um\n", infeed, twist_free);
  EXPECT_LT(twist_free, 0.2 * infeed);
}

// Issue 26: a gear ground to its drawing on an ideal machine has the drawing's crowning, by the evaluator's crowning
// (evaluation/crowning.hpp: the least-squares parabola's height over its range, along the normal) of the flank as
// ground (deviation from the design + the design). A profile crowning is dressed into the wheel and no motion is
// involved: C_α exactly as drawn, no helix crowning. (A helix crowning is ground by rigid wheel motions, which leave
// what TwistFreeMotionsLeaveLessThanAFifthOfTheRadialInfeedsTwist bounds; its evaluated C_β is printed.)
TEST(DesignMotion, AGearGroundToItsDrawingHasTheDrawingsCrowning) {
  const machine::MachineModel model(machine::Strokes::skmc_1200w(), {});
  const auto evaluated = [&](const gears::FlankModifications& m) {
    gears::GearSpec spec = test::paper_gear();
    spec.modifications = {m, m, {}};
    const grinding::GrindingSetup s(spec, {350.0, 0.0}, {});
    const auto table = compensation::design_motions(s, grinding::LeadCrowning::TwistFree, {model, 300.0});
    const grinding::IdealProcess ideal;
    const compensation::CompensatedProcess process(ideal, table);
    grinding::SimulationOptions so;
    so.teeth = {1, 18};
    so.profile_points = 100;
    so.helix_points = 150;
    auto topo = grinding::simulate_topology(s, process, so);
    for (auto& ft : topo)
      for (auto* trace : {&ft.profile, &ft.helix})
        for (auto& p : *trace) p.deviation_um += p.design_um;
    return workbench::gear_measurement(s.geometry(), s.ranges(), topo);
  };
  gears::FlankModifications profile_only;
  profile_only.profile_crowning_um = 4.0;
  const auto dressed = evaluated(profile_only);
  ASSERT_EQ(dressed.flanks.size(), 4u);
  for (const auto& f : dressed.flanks) {
    EXPECT_NEAR(evaluation::crowning_um(f.profile), 4.0, 0.01);
    EXPECT_NEAR(evaluation::crowning_um(f.helix), 0.0, 0.01);
  }
  gears::FlankModifications helix_only;
  helix_only.helix_crowning_um = kCrowningUm;
  for (const auto& f : evaluated(helix_only).flanks)
    std::printf("helix crowning %.1f um by twist-free motions: evaluated C_beta %.3f um, C_alpha %.3f um\n", kCrowningUm,
                evaluation::crowning_um(f.helix), evaluation::crowning_um(f.profile));
}

// A designed topology given as a table grinds like the same design given by its terms: the crowned default gear
// (C_α 4 µm, C_β 6 µm) tabulated on 41 × 41 nodes over the active profile and as far beyond the face as the contact
// lines reach at the stroke ends (the motions see the design there too: terms extrapolated, a table held at its
// edge), both ground twist-free on an ideal machine. They differ by the table's interpolation only: for a parabola of
// height C over L sampled every h, linear interpolation misses by at most C h²/L² (profile and helix added), doubled
// for what the dressing and the motions make of it.
TEST(DesignMotion, ATabulatedDesignGrindsLikeItsTerms) {
  const machine::MachineModel model(machine::Strokes::skmc_1200w(), {});
  gears::FlankModifications terms;
  terms.profile_crowning_um = 4.0;
  terms.helix_crowning_um = kCrowningUm;
  gears::GearSpec by_terms = test::paper_gear();
  by_terms.modifications = {terms, terms, {}};
  const grinding::GrindingSetup s_terms(by_terms, {350.0, 0.0}, {});
  const auto& g = s_terms.geometry();
  const auto& r = s_terms.ranges();
  const gears::FlankDesign& reference = s_terms.design();
  gears::DesignTable table;
  table.file = "tabulated";
  constexpr int kNodes = 41;
  const double d0 = g.root_form_diameter_mm(), d1 = g.tip_diameter_mm(), b = g.spec().face_width_mm;
  const double reach = s_terms.wheel().max_contact_offset_mm() - s_terms.wheel().min_contact_offset_mm();
  const double z0 = -reach, z1 = b + reach;
  for (int i = 0; i < kNodes; ++i) table.right.diameter_mm.push_back(d0 + (d1 - d0) * i / (kNodes - 1));
  for (int j = 0; j < kNodes; ++j) table.right.z_mm.push_back(z0 + (z1 - z0) * j / (kNodes - 1));
  for (double dy : table.right.diameter_mm)
    for (double z : table.right.z_mm) table.right.value_um.push_back(reference.at_um(Flank::Right, g.roll_length_at(dy), z));
  table.left = table.right;
  gears::GearSpec by_table = test::paper_gear();
  by_table.modifications = {{}, {}, table};
  const grinding::GrindingSetup s_table(by_table, {350.0, 0.0}, {});
  const double h_xi = (g.roll_length_at(d1) - g.roll_length_at(d0)) / (kNodes - 1), h_z = (z1 - z0) / (kNodes - 1);
  const double interpolation_um = 4.0 * h_xi * h_xi / (r.profile_evaluation_length() * r.profile_evaluation_length()) +
                                  kCrowningUm * h_z * h_z / (r.helix_evaluation_length() * r.helix_evaluation_length());
  const auto ground_um = [&](const grinding::GrindingSetup& s, int tooth, Flank f, double xi, double z) {
    const auto table_motions = compensation::design_motions(s, grinding::LeadCrowning::TwistFree, {model, 300.0});
    const grinding::IdealProcess ideal;
    const compensation::CompensatedProcess process(ideal, table_motions);
    const grinding::FlankDeviation dev(s.flanks(), s.wheel(), s.path(), process);
    const auto t = dev.target(tooth, f, xi, z);
    return 1e3 * (dev.at(t, grinding::Method::Exact).deviation_mm + t.design_mm); // the flank as ground
  };
  double worst = 0.0;
  for (auto f : {Flank::Left, Flank::Right})
    for (double xi : {r.xi_eval_start_mm, 0.5 * (r.xi_eval_start_mm + r.xi_eval_end_mm), r.xi_eval_end_mm})
      for (double z : {r.z_eval_start_mm, 60.0, r.z_eval_end_mm})
        worst = std::max(worst, std::abs(ground_um(s_table, 3, f, xi, z) - ground_um(s_terms, 3, f, xi, z)));
  std::printf("tabulated vs terms: largest difference of the ground flanks %.4f um (interpolation bound %.4f um)\n", worst,
              interpolation_um);
  EXPECT_LT(worst, 2.0 * interpolation_um);
}

namespace {

/// The CAFXZY preset with the gear's datum face 300 mm along its axis from the C table's face (the shipped scene's).
constexpr double kCafxzyDatumMm = 300.0;

/// The flank as ground (deviation from the design, µm) at tooth 3's 7×9 grid, both flanks, exact method.
std::vector<double> ground_from_design_um(const grinding::GrindingProcess& process) {
  const auto& s = setup();
  const grinding::FlankDeviation dev(s.flanks(), s.wheel(), s.path(), process);
  const Grid g = grid();
  std::vector<double> out;
  for (auto flank : {Flank::Left, Flank::Right})
    for (double xi : g.xi)
      for (double z : g.z) out.push_back(1e3 * dev.at(3, flank, xi, z, grinding::Method::Exact).deviation_mm);
  return out;
}

} // namespace

// Issue 42: the design motions in the CAFXZY's own axes, checked against its strokes. Radial infeed: its X slide
// (along the bed's x, which neither the A table's tilt about x nor the C table's turn of gear and setting alike
// changes) is the centre distance, X = x; so the one-axis least squares gives the CFXZAY's Δx at every row (to the
// solver's 1e-9 mm), every other axis exactly 0, and the commands are the closed form X = x, Y = y + (z + 150)·sin α,
// Z = (z + 150)·cos α, A = −α, C = γ (z the chain's: the gear's plus its datum face). Twist free: the five-axis least
// squares of the same flank objective, whose null directions (the screw) the two chains resolve differently (min norm
// in other axes) without changing the surface. Ground through the CAFXZY's own chain (ChainProcess on an error-free
// map: its forward kinematics, not the setting's) both give the flanks they give on the CFXZAY (IdealProcess) to
// 0.01 µm — second order in motions of tens of µm and hundreds of µrad — hence the design to the same accuracy.
TEST(DesignMotion, OnTheCafxzyTheMotionsAreItsOwnAxesAndGrindTheDesignAsOnTheCfxzay) {
  const machine::MachineModel model(machine::Strokes::skmc_1200w(), {});
  const auto& chain = *machine::chain_preset("CAFXZY");
  const grinding::IdealProcess ideal;
  const machine::MachineModel error_free(machine::Strokes::skmc_1200w(), {});
  const grinding::ChainProcess on_chain(chain, error_free, kCafxzyDatumMm);
  std::map<std::pair<int, double>, machine::AxisPose> setting; // the commands the rows stand for
  for (const auto& pp : setup().path().sample(2.0)) setting[{pp.space, pp.z_stroke_mm}] = pp.q;
  for (const auto mode : {grinding::LeadCrowning::RadialInfeed, grinding::LeadCrowning::TwistFree}) {
    const auto seed = compensation::design_motions(setup(), mode, {model, 300.0});
    const auto own = compensation::design_motions(setup(), mode, {model, kCafxzyDatumMm, &chain});
    ASSERT_FALSE(own.axes().is_setting());
    ASSERT_EQ(own.rows().size(), seed.rows().size());
    EXPECT_EQ(own.rows_outside_strokes(), 0);
    for (std::size_t i = 0; i < own.rows().size(); ++i) {
      const auto& r = own.rows()[i];
      const machine::AxisPose& q = setting.at({r.space, r.z_stroke_mm});
      const double zc = q.z + kCafxzyDatumMm + 150.0; // from the A pivot along the gear axis
      ASSERT_NEAR(r.machine_axes.x, q.x, 1e-9);
      ASSERT_NEAR(r.machine_axes.y, q.y + zc * std::sin(q.a), 1e-9);
      ASSERT_NEAR(r.machine_axes.z, zc * std::cos(q.a), 1e-9);
      ASSERT_NEAR(r.machine_axes.a, -q.a, 1e-12);
      if (mode != grinding::LeadCrowning::RadialInfeed) continue;
      ASSERT_EQ(r.correction.tail<4>().norm(), 0.0) << "X alone moves";
      ASSERT_NEAR(r.correction(0), seed.rows()[i].correction(0), 1e-9) << "ΔX = Δx, mm";
    }
    const compensation::CompensatedProcess seed_ground(ideal, seed), own_ground(on_chain, own);
    const auto a = ground_from_design_um(seed_ground), b = ground_from_design_um(own_ground);
    double differ = 0.0, largest = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
      differ = std::max(differ, std::abs(a[i] - b[i])), largest = std::max(largest, std::abs(a[i]));
    std::printf("%s: largest |deviation from the design| CFXZAY %.4f um, CAFXZY differs by %.5f um\n",
                mode == grinding::LeadCrowning::RadialInfeed ? "radial infeed" : "twist free", largest, differ);
    EXPECT_LT(differ, 0.01);
  }
}
