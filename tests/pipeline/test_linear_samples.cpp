// Linear Monte Carlo samples (docs/monte-carlo.md, "Linear samples"): the first-order sensitivities against the exact
// simulation by central finite differences, one column against an analytic answer (a C zero-position error turns the
// gear rigidly: r_b cos β_b per radian at every point), linear samples against exact samples of the same seeds, the
// check that falls back to exact samples when first order is not good enough, and the decomposition by source on
// scenes whose dominant source follows from arithmetic.
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/pipeline/topology_sensitivities.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/grinding/machine_process.hpp"
#include "geartopo/scene/scene.hpp"
#include "small_gear_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <numbers>

using namespace geartopo;

// Its own namespace: the test program is one unity build with test_monte_carlo.cpp, whose helpers have the same names.
namespace linear_samples_test {
namespace {

const std::string& kMapErrors = test::kSmallGearMapErrors;
using test::grid_of;
using test::nominal_corrections;

compensation::CorrectionTable zero_like(const compensation::CorrectionTable& t) {
  auto rows = t.rows();
  for (auto& r : rows) r.correction.setZero();
  return compensation::CorrectionTable(std::move(rows));
}

/// The exact topology (flattened, µm) of the scene's machine with component c drawn at z (ErrorSource::drawn, as a
/// Monte Carlo sample draws it) and every stroke's command off by `offset`, ground with `table`.
Eigen::VectorXd exact_with(const workbench::Workbench& wb, const grinding::TopologyPlan& plan,
                           const compensation::CorrectionTable& table, int c, double z, const machine::Vector5d& offset) {
  std::vector<machine::ErrorSource> map;
  for (int k = 0; k < machine::kComponentCount; ++k) map.push_back(machine::ErrorSource::zero(machine::component_at(k)));
  for (const auto& s : wb.scene.machine.sources) map[static_cast<size_t>(machine::index(s.id()))] = s;
  if (c >= 0) map[static_cast<size_t>(c)] = map[static_cast<size_t>(c)].drawn(z, wb.scene.machine.uncertainty.component_u[static_cast<size_t>(c)]);
  const machine::MachineModel model(wb.machine.strokes(), std::move(map));
  const grinding::MachineProcess process(model, wb.scene.machine.datum_face_z_mm);
  auto rows = table.rows();
  for (auto& r : rows) r.correction += offset;
  const compensation::CorrectionTable shifted(std::move(rows));
  const compensation::CompensatedProcess ground(process, shifted);
  return pipeline::flatten_deviations(plan.simulate(ground, 0));
}

} // namespace

// Each map column and each stroke column against the central difference (f(+h) − f(−h))/2h of the exact simulation
// (the exact envelope of the wheel at its exact poses; no first-order model in it), for gear 1 (uncorrected) and gear 2
// (corrected, rounded or not). The first-order model evaluates each point at its generating pose Z₀; the machine's own
// errors (here up to 11 µm on gear 1) move the deepest cut along the stroke, where the sensitivities differ slightly:
// that is the linear model's error, measured 0.22 % of a column's largest value on gear 1 and 0.01 % on the corrected
// gear 2 (its errors are gone); in absolute terms at most 0.002 µm per unit draw. Allowed: 1 % of the column's largest
// value, and of 0.2 µm for the small columns (0.002 µm): a sample's deviation from the nominal gear of a few µm is
// then right to a few hundredths of a µm, within the run's 0.05 µm check.
constexpr double kFirstOrderShare = 0.01, kColumnFloorUm = 0.2;

TEST(TopologySensitivities, ColumnsAreFiniteDifferencesOfTheExactSimulation) {
  const workbench::Workbench wb(scene::parse_scene(test::small_gear_scene_text(kMapErrors), "mem"));
  const auto nominal = nominal_corrections(wb);
  const auto applied = pipeline::rounded_to_resolution(nominal, wb.scene.machine.uncertainty.resolution);
  const grinding::TopologyPlan plan(wb.setup, grid_of(wb));
  for (const auto* table : {&nominal, &applied}) {
    const auto uncorrected = zero_like(*table);
    for (const auto* t : {&uncorrected, table}) {
      const auto s = pipeline::topology_sensitivities(wb, plan, *t, 0);
      ASSERT_EQ(s.nominal_um.size(), static_cast<Eigen::Index>(plan.points()));
      const auto base = exact_with(wb, plan, *t, -1, 0.0, machine::Vector5d::Zero());
      EXPECT_LT((s.nominal_um - base).cwiseAbs().maxCoeff(), 1e-9) << "the nominal gear is the exact one";
      for (const auto id : {machine::ComponentId::delta_xx, machine::ComponentId::epsilon_zx, machine::ComponentId::delta_yz,
                            machine::ComponentId::epsilon_xa, machine::ComponentId::epsilon_zc, machine::ComponentId::S_xz,
                            machine::ComponentId::E_YOA, machine::ComponentId::E_COC}) {
        const int c = machine::index(id);
        const Eigen::VectorXd fd =
            (exact_with(wb, plan, *t, c, 1.0, machine::Vector5d::Zero()) - exact_with(wb, plan, *t, c, -1.0, machine::Vector5d::Zero())) / 2.0;
        const double largest = fd.cwiseAbs().maxCoeff();
        ASSERT_GT(largest, 0.04) << machine::info(id).name << ": a column that matters";
        EXPECT_LT((s.map_um.col(c) - fd).cwiseAbs().maxCoeff(), kFirstOrderShare * std::max(largest, kColumnFloorUm))
            << machine::info(id).name;
      }
      for (int axis = 0; axis < 5; ++axis) {
        const double h = axis < 3 ? units::mm_from_um(1.0) : 1e-6; // 1 µm, 1 µrad
        machine::Vector5d off = machine::Vector5d::Zero();
        off(axis) = h;
        const Eigen::VectorXd fd = (exact_with(wb, plan, *t, -1, 0.0, off) - exact_with(wb, plan, *t, -1, 0.0, -off)) / 2.0;
        ASSERT_GT(fd.cwiseAbs().maxCoeff(), 0.005) << "axis " << axis << ": an offset that matters";
        EXPECT_LT((s.stroke_um.col(axis) * h - fd).cwiseAbs().maxCoeff(), kFirstOrderShare * std::max(fd.cwiseAbs().maxCoeff(), kColumnFloorUm))
            << "axis " << axis;
      }
    }
  }
}

// A C zero-position error E_COC turns the whole gear about its axis: every flank point moves along its normal by
// r_b cos β_b per radian (the normal of an involute helicoid has the tangential component cos β_b at the base radius),
// left and right flanks in opposite senses. So E_COC's column is ±r_b cos β_b u at every point, from ISO 21771 alone.
TEST(TopologySensitivities, TheCIndexColumnIsTheRigidRotationOfTheGear) {
  const std::string only_c = "  uncertainty: {components: {E_COC_urad: 20}}\n";
  const workbench::Workbench wb(scene::parse_scene(test::small_gear_scene_text(only_c), "mem"));
  const grinding::TopologyPlan plan(wb.setup, grid_of(wb));
  const auto s = pipeline::topology_sensitivities(wb, plan, zero_like(nominal_corrections(wb)), 0);
  const double beta = 20.0 * std::numbers::pi / 180.0, alpha_n = beta;
  const double rb = 0.5 * 20 * 4.0 / std::cos(beta) * std::cos(std::atan(std::tan(alpha_n) / std::cos(beta)));
  const double beta_b = std::asin(std::sin(beta) * std::cos(alpha_n));
  const double expected_um = rb * std::cos(beta_b) * 20e-6 * 1e3; // mm · rad → µm
  const Eigen::VectorXd col = s.map_um.col(machine::index(machine::ComponentId::E_COC));
  const auto contacts = plan.linear_contacts();
  ASSERT_EQ(static_cast<size_t>(col.size()), contacts.size());
  // The sign by flank: the point's normal (out of the material) turns one way on a left flank, the other on a right.
  double left = 0.0, right = 0.0;
  for (Eigen::Index i = 0; i < col.size(); ++i) {
    EXPECT_NEAR(std::abs(col(i)), expected_um, 1e-9 * expected_um);
    (contacts[static_cast<size_t>(i)].n.cross(contacts[static_cast<size_t>(i)].p).z() > 0 ? left : right) += col(i);
  }
  EXPECT_LT(left * right, 0.0);
}

namespace {

double band_of(const pipeline::MonteCarloSummary& s, const std::string& name, bool after, double pipeline::Band::*m) {
  const int i = s.find(name);
  EXPECT_GE(i, 0) << name;
  return i < 0 ? 0.0 : (after ? s.after : s.before)[static_cast<size_t>(i)].*m;
}

} // namespace

// The same samples (seeds 0 … 29 of seed 3) computed exactly and to first order on a machine with map errors, the
// default uncertainties (1–5 µm, 3–5 µrad), repeatability (R↑ 3 µm, 1 mdeg) and resolution (1 µm, 1 mdeg): every µm
// quantity of every sample within 2 × kLinearAgreementUm (a point moved by δ moves a range or a pitch by at most 2δ),
// so the medians and interval ends too; the checked run takes the linear samples, bit for bit those of the unchecked
// one, and says how far its 4 exact samples were.
TEST(LinearSamples, AgreeWithExactSamplesOfTheSameSeeds) {
  const workbench::Workbench wb(scene::parse_scene(test::small_gear_scene_text(kMapErrors), "mem"));
  const auto table = nominal_corrections(wb);
  pipeline::MonteCarloOptions o;
  o.samples = 30;
  o.seed = 3;
  o.sampling = pipeline::Sampling::Exact;
  const auto exact = pipeline::run_monte_carlo(wb, table, o);
  o.sampling = pipeline::Sampling::Linear;
  const auto linear = pipeline::run_monte_carlo(wb, table, o);
  o.sampling = pipeline::Sampling::Checked;
  const auto checked = pipeline::run_monte_carlo(wb, table, o);
  ASSERT_EQ(exact.names, linear.names);
  EXPECT_EQ(exact.sampling.method, "exact");
  EXPECT_EQ(checked.sampling.method, "linear");
  EXPECT_EQ(checked.sampling.reason, "checked");
  EXPECT_EQ(checked.sampling.checked_samples, pipeline::kCheckSamples);
  EXPECT_LE(checked.sampling.largest_quantity_difference_um, pipeline::kLinearAgreementUm);
  ASSERT_EQ(checked.samples.size(), linear.samples.size());
  double worst = 0.0;
  for (size_t k = 0; k < exact.samples.size(); ++k) {
    EXPECT_EQ(checked.samples[k].after, linear.samples[k].after);
    for (size_t n = 0; n < exact.names.size(); ++n) {
      if (!exact.names[n].ends_with("_um")) continue;
      for (const bool after : {false, true}) {
        const double e = after ? exact.samples[k].after[n] : exact.samples[k].before[n];
        const double l = after ? linear.samples[k].after[n] : linear.samples[k].before[n];
        worst = std::max(worst, std::abs(e - l));
        EXPECT_NEAR(l, e, 2 * pipeline::kLinearAgreementUm) << "sample " << k << " " << (after ? "after." : "before.") << exact.names[n];
      }
    }
  }
  std::cout << "largest |linear − exact| of a µm quantity over 30 samples: " << worst << " µm\n";
  const auto se = pipeline::summarise(exact), sl = pipeline::summarise(linear);
  for (const auto& name : exact.names) {
    if (!name.ends_with("_um")) continue;
    for (const bool after : {false, true})
      for (const auto m : {&pipeline::Band::median, &pipeline::Band::low, &pipeline::Band::high}) {
        EXPECT_NEAR(band_of(sl, name, after, m), band_of(se, name, after, m), 2 * pipeline::kLinearAgreementUm) << name;
      }
  }
}

// Calibration offsets of 50 µm (the u of every linear component) are not small on a gear of module 4: the wheel moved
// by 0.1 mm across the flank touches it elsewhere along its profile and the stroke, which first order at the nominal
// contact does not see (measured: 2.8 µm in a quantity, 4.2 µm at a point). So the check fails, the run's samples are
// the exact ones, bit for bit, and it says so. (Milliradian rotary offsets, which would do the same, move the wheel off
// this small gear's flanks altogether.)
TEST(LinearSamples, FallBackToExactSamplesWhenFirstOrderIsNotGoodEnough) {
  const std::string large = kMapErrors + "  uncertainty: {linear_axis_um: 50, rotary_axis_um: 50}\n";
  const workbench::Workbench wb(scene::parse_scene(test::small_gear_scene_text(large), "mem"));
  const auto table = nominal_corrections(wb);
  pipeline::MonteCarloOptions o;
  o.samples = 4;
  const auto checked = pipeline::run_monte_carlo(wb, table, o);
  EXPECT_EQ(checked.sampling.method, "exact");
  EXPECT_EQ(checked.sampling.reason, "check failed");
  EXPECT_GT(checked.sampling.largest_quantity_difference_um, pipeline::kLinearAgreementUm);
  std::cout << "50 µm offsets: first order off by " << checked.sampling.largest_quantity_difference_um << " µm (a quantity), "
            << checked.sampling.largest_point_difference_um << " µm (a point)\n";
  EXPECT_TRUE(checked.without.empty()) << "no decomposition from exact samples";
  o.sampling = pipeline::Sampling::Exact;
  const auto exact = pipeline::run_monte_carlo(wb, table, o);
  ASSERT_EQ(checked.samples.size(), exact.samples.size());
  for (size_t k = 0; k < exact.samples.size(); ++k) EXPECT_EQ(checked.samples[k].after, exact.samples[k].after);
}

namespace {

pipeline::AfterLimit limit_of(const std::string& machine) {
  const workbench::Workbench wb(scene::parse_scene(test::small_gear_scene_text(machine), "mem"));
  pipeline::MonteCarloOptions o;
  o.samples = 40;
  const auto s = pipeline::summarise(pipeline::run_monte_carlo(wb, nominal_corrections(wb), o));
  EXPECT_EQ(s.sampling.method, "linear");
  return pipeline::after_limit(s);
}

const pipeline::SourceEffect* without_source(const pipeline::AfterLimit& l, const std::string& source) {
  for (const auto& w : l.without)
    if (w.source == source) return &w;
  ADD_FAILURE() << source << " not switched off";
  return nullptr;
}

} // namespace

// The command resolution sets the class: C and A rounded to 2 mdeg (35 µrad: up to ±17 µrad of rounding error,
// r_b cos β_b · 17 µrad ≈ 0.6 µm on this gear's flanks, as steps along the strokes where the corrections cross a
// step) against a repeatability of R↑ 0.04 µm / 0.004 mdeg (s = 0.01 µm, 0.001 mdeg: 0.0006 µm on the flank) and no
// map uncertainty. Without the rounding the after-gear is the nominally corrected one plus the scatter: its limiting
// value falls by the rounding's share, ten times more than without the repeatability.
TEST(LinearSamples, TheResolutionSetsTheClassWhenItsStepsDominate) {
  const auto l = limit_of(kMapErrors +
                          "  uncertainty: {linear_axis_um: 0, linear_axis_urad: 0, rotary_axis_um: 0, rotary_axis_urad: 0,\n"
                          "                squareness_urad: 0, location_um: 0, location_urad: 0}\n"
                          "  repeatability: {x_um: 0.04, y_um: 0.04, z_um: 0.04, a_mdeg: 0.004, c_mdeg: 0.004}\n"
                          "  resolution: {x_um: 1, y_um: 1, z_um: 1, a_mdeg: 2, c_mdeg: 2}\n");
  ASSERT_TRUE(l.measured);
  EXPECT_EQ(l.dominant, "resolution_rounding");
  const auto* rounding = without_source(l, "resolution_rounding");
  const auto* repeat = without_source(l, "repeatability");
  ASSERT_TRUE(rounding && repeat);
  EXPECT_GT(l.limiting_median_um - rounding->limiting_median_um, 10 * (l.limiting_median_um - repeat->limiting_median_um))
      << l.limiting_quantity;
}

// The repeatability sets the class: each stroke's C off by s = 1 mdeg (R↑ 4 mdeg: 17.5 µrad, r_b cos β_b s ≈ 0.65 µm
// per stroke, so single and cumulative pitch of several µm) and X, Y, Z by s = 3 µm, against a resolution of 0.01 µm
// and 0.001 mdeg (rounding errors of 0.0003 µm on the flank) and no map uncertainty: only without the repeatability does
// the limiting value (a pitch) fall.
TEST(LinearSamples, TheRepeatabilitySetsTheClassWhenTheStrokesScatter) {
  const auto l = limit_of(kMapErrors +
                          "  uncertainty: {linear_axis_um: 0, linear_axis_urad: 0, rotary_axis_um: 0, rotary_axis_urad: 0,\n"
                          "                squareness_urad: 0, location_um: 0, location_urad: 0}\n"
                          "  repeatability: {x_um: 12, y_um: 12, z_um: 12, a_mdeg: 4, c_mdeg: 4}\n"
                          "  resolution: {x_um: 0.01, y_um: 0.01, z_um: 0.01, a_mdeg: 0.001, c_mdeg: 0.001}\n");
  ASSERT_TRUE(l.measured);
  EXPECT_EQ(l.dominant, "repeatability");
  const auto* rounding = without_source(l, "resolution_rounding");
  const auto* repeat = without_source(l, "repeatability");
  ASSERT_TRUE(rounding && repeat);
  EXPECT_LT(repeat->overall_class, l.overall_class);
  EXPECT_NEAR(rounding->limiting_median_um, l.limiting_median_um, 0.01);
}

} // namespace linear_samples_test
