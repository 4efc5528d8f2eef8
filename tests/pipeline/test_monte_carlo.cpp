// Monte Carlo after-state: truths from outside the code — the GUM S1 order statistics written out, the normal
// distribution of a rigid rotation by a C zero-position error, the uniform error of rounding, the nominal simulation
// when nothing is uncertain, and the identity of sample k whatever the threads or shards.
#include "geartopo/pipeline/monte_carlo.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/identified_effects.hpp"
#include "geartopo/measurement/measured_points.hpp"
#include "geartopo/diagnosis/stroke_scatter.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/evaluation/gear_evaluation.hpp"
#include "geartopo/scene/scene.hpp"
#include "small_gear_scene.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sys/wait.h>
#include <unistd.h>

using namespace geartopo;

namespace {

// A small helical gear (fast to simulate), no error tables; `machine_extra` is appended to the machine section.
std::string mc_scene_text(const std::string& machine_extra) { return test::small_gear_scene_text(machine_extra); }

const std::string kNothingUncertain =
    "  uncertainty: {linear_axis_um: 0, linear_axis_urad: 0, rotary_axis_um: 0, rotary_axis_urad: 0,\n"
    "                squareness_urad: 0, location_um: 0, location_urad: 0}\n"
    "  repeatability: {x_um: 0, y_um: 0, z_um: 0, a_mdeg: 0, c_mdeg: 0}\n"
    "  resolution: {x_um: 0, y_um: 0, z_um: 0, a_mdeg: 0, c_mdeg: 0}\n";

const std::string& kMapErrors = test::kSmallGearMapErrors;
using test::grid_of;
using test::nominal_corrections;

double value_of(const pipeline::GearQuantities& g, const std::string& name) {
  for (size_t i = 0; i < g.names.size(); ++i)
    if (g.names[i] == name) return g.values[i];
  ADD_FAILURE() << name << " missing";
  return 0.0;
}

// The scene with only the C zero position uncertain (E_COC, u = 20 µrad): no other uncertainty, repeatability or
// resolution.
const std::string kOnlyCIndexUncertain =
    "  uncertainty: {linear_axis_um: 0, linear_axis_urad: 0, rotary_axis_um: 0, rotary_axis_urad: 0,\n"
    "                squareness_urad: 0, location_um: 0, location_urad: 0,\n"
    "                components: {E_COC_urad: 20}}\n"
    "  repeatability: {x_um: 0, y_um: 0, z_um: 0, a_mdeg: 0, c_mdeg: 0}\n"
    "  resolution: {x_um: 0, y_um: 0, z_um: 0, a_mdeg: 0, c_mdeg: 0}\n";

/// σ of the rotation line (µm) for a C zero-position error of standard uncertainty u (µrad) on mc_scene_text's gear:
/// r_b cos β_b u, by ISO 21771 from the gear data (d = z m_n / cos β, tan α_t = tan α_n / cos β, d_b = d cos α_t,
/// sin β_b = sin β cos α_n).
double rotation_sd_um(double u_urad) {
  const double beta = 20.0 * units::kRadPerDeg, alpha_n = 20.0 * units::kRadPerDeg;
  const double d = 20 * 4.0 / std::cos(beta);
  const double rb = 0.5 * d * std::cos(std::atan(std::tan(alpha_n) / std::cos(beta)));
  const double beta_b = std::asin(std::sin(beta) * std::cos(alpha_n));
  return rb * std::cos(beta_b) * u_urad * 1e-3; // mm·µrad → nm; ·1e-3 → µm
}

} // namespace

// JCGM 101:2008 §7.7, probabilistically symmetric 95 %: M = 1000 sorted values → q = 950, r = 25: [y_25, y_975].
TEST(MonteCarloBand, OrderStatisticsOfGumSupplement1) {
  std::vector<double> v;
  for (int i = 1000; i >= 1; --i) v.push_back(i); // y_(i) = i once sorted
  const auto b = pipeline::coverage_band(v);
  EXPECT_EQ(b.low, 25.0);
  EXPECT_EQ(b.high, 975.0);
  EXPECT_EQ(b.median, 500.5);
  // M = 41: pM = 38.95 → q = 39, M − q = 2 → r = 1: [y_1, y_40]; median y_21.
  std::vector<double> w;
  for (int i = 1; i <= 41; ++i) w.push_back(i);
  const auto c = pipeline::coverage_band(w);
  EXPECT_EQ(c.low, 1.0);
  EXPECT_EQ(c.high, 40.0);
  EXPECT_EQ(c.median, 21.0);
}

// The scene's uncertainty keys: documented defaults when absent, per-kind values, one component overridden, and a
// negative value refused at its line.
TEST(SceneUncertainty, DefaultsKindsAndComponents) {
  const auto d = scene::parse_scene(mc_scene_text(""), "mem");
  const auto& u = d.machine.uncertainty;
  using machine::ComponentId;
  const auto at = [](const scene::MachineUncertainty& x, ComponentId id) { return x.component_u[static_cast<size_t>(machine::index(id))]; };
  EXPECT_DOUBLE_EQ(at(u, ComponentId::delta_xx), 1e-3);   // 1 µm
  EXPECT_DOUBLE_EQ(at(u, ComponentId::epsilon_zz), 3e-6); // 3 µrad
  EXPECT_DOUBLE_EQ(at(u, ComponentId::delta_yc), 2e-3);   // 2 µm
  EXPECT_DOUBLE_EQ(at(u, ComponentId::epsilon_zc), 5e-6); // 5 µrad
  EXPECT_DOUBLE_EQ(at(u, ComponentId::S_xy), 5e-6);
  // Repeatability R↑ = 3 µm, 1 mdeg is 4 standard deviations (ISO 230-2).
  EXPECT_DOUBLE_EQ(u.repeatability(0), 0.75e-3);
  EXPECT_DOUBLE_EQ(u.repeatability(4), 0.25 * std::numbers::pi / 180e3);
  EXPECT_DOUBLE_EQ(u.resolution(2), 1e-3);

  const auto s = scene::parse_scene(
      mc_scene_text("  uncertainty: {rotary_axis_urad: 7, components: {epsilon_zc_urad: 2, E_XOC_um: 0.5}}\n"
                    "  repeatability: {c_mdeg: 0.5}\n"),
      "mem");
  const auto& v = s.machine.uncertainty;
  EXPECT_DOUBLE_EQ(at(v, ComponentId::epsilon_xa), 7e-6);
  EXPECT_DOUBLE_EQ(at(v, ComponentId::epsilon_zc), 2e-6);
  EXPECT_DOUBLE_EQ(at(v, ComponentId::E_XOC), 0.5e-3);
  EXPECT_DOUBLE_EQ(v.repeatability(4), 0.125 * std::numbers::pi / 180e3);
  EXPECT_DOUBLE_EQ(v.repeatability(0), 0.75e-3); // untouched: default

  try {
    scene::parse_scene(mc_scene_text("  repeatability: {x_um: -1}\n"), "bad.yaml");
    FAIL() << "a negative repeatability was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml:10:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("machine.repeatability.x_um"), std::string::npos) << e.what();
  }
  EXPECT_THROW(scene::parse_scene(mc_scene_text("  uncertainty: {components: {epsilon_zc_um: 2}}\n"), "bad.yaml"),
               InputError); // a length unit for an angle
}

// With nothing uncertain, every sample is the nominal simulation: before = the scene's gear, after = the gear
// ground with the nominal corrections (computed here the way `compensate` does).
TEST(MonteCarlo, NothingUncertainReproducesTheNominalGears) {
  const workbench::Workbench wb(scene::parse_scene(mc_scene_text(kMapErrors + kNothingUncertain), "mem"));
  const auto table = nominal_corrections(wb);
  const auto so = grid_of(wb);
  const auto& g = wb.setup.geometry();
  const auto before = grinding::simulate_topology(wb.setup, wb.process(), so);
  const compensation::CompensatedProcess corrected(wb.process(), table);
  const auto after = grinding::simulate_topology(wb.setup, corrected, so);
  const auto qb = pipeline::gear_quantities(workbench::evaluate_iso(g, wb.setup.ranges(), before), before);
  const auto qa = pipeline::gear_quantities(workbench::evaluate_iso(g, wb.setup.ranges(), after), after);
  ASSERT_GT(value_of(qb, "largest_abs_um"), 2.0); // the map errors matter …
  ASSERT_LT(value_of(qa, "largest_abs_um"), 0.1); // … and the nominal compensation removes them

  pipeline::MonteCarloOptions o;
  o.samples = 3;
  const auto run = pipeline::run_monte_carlo(wb, table, o);
  ASSERT_EQ(run.names, qb.names);
  // The Monte Carlo grinds through a TopologyPlan, whose exact search takes the depth's curvature from the ideal
  // process (3 poses per point); simulate_topology above searches without it (4 poses). Both land within ~1e-10 mm of
  // the true deepest cut, and the plan is held to the plain path at 1e-6 µm (TopologyPlan.*, docs/grinding.md): that
  // is the bound here too, 10⁴ below the 0.01 µm a flank is reported to: a draw leaking into a sample still fails it.
  constexpr double kSearchAgreementUm = 1e-6;
  for (const auto& s : run.samples)
    for (size_t i = 0; i < run.names.size(); ++i) {
      EXPECT_NEAR(s.before[i], qb.values[i], kSearchAgreementUm) << run.names[i];
      EXPECT_NEAR(s.after[i], qa.values[i], kSearchAgreementUm) << run.names[i];
    }
}

namespace {

/// The rotation line of both gears is N(0, σ²) over 200 samples. Standard errors of the sample quantiles of N(0, σ²) for
/// M = 200: median 1.2533 σ/√M = 0.089 σ; the 2.5 % and 97.5 % quantiles √(p(1−p)/M)/φ(1.96) σ = 0.189 σ. Allowed:
/// three standard errors.
void expect_normal_rotation(const pipeline::MonteCarloSummary& s, double sigma_um) {
  for (const auto* side : {&s.before, &s.after}) {
    const auto& rot = (*side)[static_cast<size_t>(s.find("rotation_um"))];
    EXPECT_NEAR(rot.median, 0.0, 3 * 0.089 * sigma_um);
    EXPECT_NEAR(rot.low, -1.96 * sigma_um, 3 * 0.189 * sigma_um);
    EXPECT_NEAR(rot.high, 1.96 * sigma_um, 3 * 0.189 * sigma_um);
  }
}

} // namespace

// A C zero-position error E_COC of standard uncertainty u and nothing else turns the whole gear about its axis by
// u·N(0, 1): every flank moves along its normal by r_b·cos β_b·E_COC, left and right in opposite senses. So the
// rotation line is N(0, σ²) with σ = r_b cos β_b u, and pitch (F_p), thickness and flank form do not change.
TEST(MonteCarlo, UncertainCIndexIsANormallyDistributedRigidRotation) {
  const double u_urad = 20.0;
  const workbench::Workbench wb(scene::parse_scene(mc_scene_text(kOnlyCIndexUncertain), "mem"));
  const double sigma_um = rotation_sd_um(u_urad);

  pipeline::MonteCarloOptions o;
  o.samples = 200;
  o.seed = 7;
  const auto s = pipeline::summarise(pipeline::run_monte_carlo(wb, nominal_corrections(wb), o));
  expect_normal_rotation(s, sigma_um);
  for (const auto* side : {&s.before, &s.after}) {
    const auto& fp = (*side)[static_cast<size_t>(s.find("F_p_um"))];
    EXPECT_LT(fp.high, 0.01 * sigma_um) << "a rigid rotation changed the pitch";
    const auto& th = (*side)[static_cast<size_t>(s.find("thickness_um"))];
    EXPECT_LT(std::max(std::abs(th.low), std::abs(th.high)), 0.01 * sigma_um);
  }
}

// The same rotation from a machine change instead of the map: E_COC changed by 0 ± 20 µrad (scene key
// machine_changes with its uncertainty, as diagnose writes a change it found) and nothing else uncertain. The
// prediction draws the change's size within its σ: the rotation line is N(0, (r_b cos β_b u)²) again.
TEST(MonteCarlo, AnUncertainMachineChangeIsDrawnWithinItsSigma) {
  const double u_urad = 20.0;
  const workbench::Workbench wb(scene::parse_scene(
      mc_scene_text(kNothingUncertain) + "machine_changes:\n  - {component: E_COC, change_urad: 0, uncertainty: {change_urad: 20}}\n",
      "mem"));
  ASSERT_EQ(wb.scene.machine_change_uncertainties, std::vector<double>{20.0});
  const double sigma_um = rotation_sd_um(u_urad);
  pipeline::MonteCarloOptions o;
  o.samples = 200;
  o.seed = 7;
  expect_normal_rotation(pipeline::summarise(pipeline::run_monte_carlo(wb, nominal_corrections(wb), o)), sigma_um);
}

namespace {

/// Gear 1 (no corrections) and gear 2 (with `table`) of the small gear on the map kMapErrors, nothing uncertain, with a
/// thermal drift of x growth `x_um` and time constant `tau_s` (z growth 0), simulated here.
std::pair<pipeline::GearQuantities, pipeline::GearQuantities> gears_with_drift(double x_um, double tau_s,
                                                                              const compensation::CorrectionTable& table) {
  const workbench::Workbench wb(scene::parse_scene(
      mc_scene_text(kMapErrors + kNothingUncertain) +
          fmt::format("effects:\n  - {{type: thermal_drift, x_growth_um: {}, time_constant_s: {}}}\n", x_um, tau_s),
      "mem"));
  const auto so = grid_of(wb);
  const auto& g = wb.setup.geometry();
  const auto before = grinding::simulate_topology(wb.setup, wb.process(), so);
  const compensation::CompensatedProcess corrected(wb.process(), table);
  const auto after = grinding::simulate_topology(wb.setup, corrected, so);
  return {pipeline::gear_quantities(workbench::evaluate_iso(g, wb.setup.ranges(), before), before),
          pipeline::gear_quantities(workbench::evaluate_iso(g, wb.setup.ranges(), after), after)};
}

bool same_gear(const std::vector<double>& sample, const pipeline::GearQuantities& q) {
  for (size_t i = 0; i < q.values.size(); ++i)
    if (!(std::abs(sample[i] - q.values[i]) <= 1e-6)) return false; // the plan's search agreement (above)
  return true;
}

} // namespace

// An effect drawn from value sets (Scene::effect_draws; docs/monte-carlo.md): each sample grinds both its gears with
// one whole set — nothing between, nothing outside — picked with equal probability, the same set for gear 1 and gear 2.
// Two sets (x growth 0 and 20 µm, τ 120 s) on a machine with nothing else uncertain: every sample's gears are those
// simulated here with one of the two drifts (exact samples, within the search agreement 1e-6 µm), and set 2's count in
// 80 samples is Binomial(80, 1/2): within 4σ = 17.9 of 40. The samples are the same at 1 and 2 threads, bit for bit.
TEST(MonteCarloEffectSets, EachSampleGrindsBothGearsWithOneWholeSet) {
  const workbench::Workbench wb(scene::parse_scene(
      mc_scene_text(kMapErrors + kNothingUncertain) +
          "effects:\n  - type: thermal_drift\n    x_growth_um: 10\n    time_constant_s: 120\n"
          "    draws: {keys: [x_growth_um], sets: [[0], [20]]}\n",
      "mem"));
  ASSERT_EQ(wb.scene.effect_draws.size(), 1u);
  const auto table = nominal_corrections(wb); // from the scene's own value, x growth 10 µm
  const auto [cold1, cold2] = gears_with_drift(0.0, 120.0, table);
  const auto [warm1, warm2] = gears_with_drift(20.0, 120.0, table);
  ASSERT_GT(std::abs(value_of(warm1, "thickness_um") - value_of(cold1, "thickness_um")), 1.0); // the sets differ
  pipeline::MonteCarloOptions o;
  o.samples = 80;
  o.seed = 5;
  o.sampling = pipeline::Sampling::Exact;
  o.threads = 1;
  const auto run = pipeline::run_monte_carlo(wb, table, o);
  int warm = 0;
  for (const auto& s : run.samples) {
    const bool is_cold = same_gear(s.before, cold1), is_warm = same_gear(s.before, warm1);
    ASSERT_NE(is_cold, is_warm) << "sample " << s.index << " ground gear 1 with neither set (or both)";
    EXPECT_TRUE(same_gear(s.after, is_warm ? warm2 : cold2)) << "sample " << s.index << ": gear 2 with another set";
    warm += is_warm ? 1 : 0;
  }
  EXPECT_NEAR(warm, 40, 4.0 * std::sqrt(80 * 0.25));
  o.threads = 2;
  const auto again = pipeline::run_monte_carlo(wb, table, o);
  for (size_t k = 0; k < run.samples.size(); ++k) {
    EXPECT_EQ(run.samples[k].before, again.samples[k].before) << k;
    EXPECT_EQ(run.samples[k].after, again.samples[k].after) << k;
  }
}

// A Gaussian effect value is truncated to its allowed range by drawing again, never held at the bound: a time
// constant of 20 ± 40 s (allowed: ≥ 10 s) held at its bound would make 40 % of the samples (z < −0.25) grind with
// exactly τ = 10 s (P(none of 60) = 0.6⁶⁰ ≈ 5e-14). Drawn again, no sample does (exact samples: gear 1 with τ = 10 s
// simulated here, within 1e-6 µm).
TEST(MonteCarloEffectDraws, AGaussianValueOutsideItsRangeIsDrawnAgainNotHeldAtTheBound) {
  const workbench::Workbench wb(scene::parse_scene(
      mc_scene_text(kMapErrors + kNothingUncertain) +
          "effects:\n  - type: thermal_drift\n    x_growth_um: 20\n    time_constant_s: 20\n"
          "    uncertainty: {time_constant_s: 40}\n",
      "mem"));
  const auto table = nominal_corrections(wb);
  const auto at_bound = gears_with_drift(20.0, 10.0, table).first;
  pipeline::MonteCarloOptions o;
  o.samples = 60;
  o.seed = 9;
  o.sampling = pipeline::Sampling::Exact;
  const auto run = pipeline::run_monte_carlo(wb, table, o);
  for (const auto& s : run.samples) EXPECT_FALSE(same_gear(s.before, at_bound)) << "sample " << s.index << " held at τ = 10 s";
}

// Rounding to a step q leaves an error uniform on [−q/2, q/2]: standard deviation q/√12 (GUM 4.3.7), never more than
// q/2. Checked on the corrections of a gear whose corrections spread over many steps, for the axes whose command
// stands still along a stroke (X, Y, A): the controller rounds the setpoint, and on the axes a stroke sweeps (Z, C:
// thousands of steps between rows) the error averages out (test_command_resolution.cpp).
TEST(MonteCarlo, RoundingToTheResolutionErrsUniformly) {
  // A roll of the Z carriage growing along Z: C corrections that vary along every stroke.
  const workbench::Workbench wb(scene::parse_scene(
      mc_scene_text(kMapErrors + "  polynomials: {epsilon_zz: {unit: urad, position_unit: mm, coefficients: [0, 0.2]}}\n"),
      "mem"));
  const auto table = nominal_corrections(wb);
  machine::Vector5d q;
  q << 0.05e-3, 0.05e-3, 0.05e-3, 0.01e-6, 0.01e-6; // 0.05 µm, 0.01 µrad
  const auto rounded = pipeline::rounded_to_resolution(table, q);
  ASSERT_EQ(rounded.rows().size(), table.rows().size());
  const auto n = static_cast<double>(table.rows().size());
  ASSERT_GT(n, 300);
  int axes_checked = 0;
  for (int axis = 0; axis < 5; ++axis) {
    double sum_sq = 0.0, lo = 1e300, hi = -1e300;
    const bool moves = axis == 2 || axis == 4; // Z and C: the stroke
    for (size_t i = 0; i < table.rows().size(); ++i) {
      const double e = rounded.rows()[i].correction(axis) - table.rows()[i].correction(axis);
      EXPECT_LE(std::abs(e), (moves ? 1e-3 : 0.5) * q(axis) * (1 + 1e-12)) << "axis " << axis;
      sum_sq += e * e;
      lo = std::min(lo, table.rows()[i].correction(axis));
      hi = std::max(hi, table.rows()[i].correction(axis));
    }
    // The uniform law needs corrections that vary over many steps (a constant correction errs by one fixed amount).
    if (moves || hi - lo < 20 * q(axis)) continue;
    ++axes_checked;
    // Relative standard error of an RMS of n uniform errors: √(4/5)/(2√n) ≈ 0.45/√n. Allowed: four of them.
    EXPECT_NEAR(std::sqrt(sum_sq / n), q(axis) / std::sqrt(12.0), 4 * 0.45 / std::sqrt(n) * q(axis) / std::sqrt(12.0))
        << "axis " << axis;
  }
  EXPECT_GE(axes_checked, 2);
}

// Sample k depends on (seed, k) only: 1 or 2 threads, one run or three shards written, read back and merged — the
// same numbers bit for bit; another seed gives other numbers.
TEST(MonteCarlo, ShardsAndThreadsGiveTheSameSamplesBitForBit) {
  const workbench::Workbench wb(scene::parse_scene(mc_scene_text(kMapErrors), "mem"));
  const auto table = nominal_corrections(wb);
  pipeline::MonteCarloOptions o;
  o.samples = 7;
  o.seed = 42;
  o.threads = 1;
  const auto one = pipeline::run_monte_carlo(wb, table, o);
  o.threads = 2;
  const auto two = pipeline::run_monte_carlo(wb, table, o);
  const auto dir = std::filesystem::temp_directory_path() / "geartopo_test_mc_shards";
  std::filesystem::create_directories(dir);
  std::vector<pipeline::MonteCarloRun> parts;
  o.shards = 3;
  for (int i = 3; i >= 1; --i) { // out of order on purpose
    o.shard = i;
    const auto file = dir / ("part" + std::to_string(i) + ".csv");
    pipeline::write_run_csv(file, pipeline::run_monte_carlo(wb, table, o));
    parts.push_back(pipeline::read_run_csv(file));
  }
  const auto merged = pipeline::merge_runs(parts);
  ASSERT_EQ(one.samples.size(), 7u);
  for (const auto* other : {&two, &merged}) {
    ASSERT_EQ(other->names, one.names);
    ASSERT_EQ(other->samples.size(), one.samples.size());
    for (size_t k = 0; k < one.samples.size(); ++k) {
      EXPECT_EQ(other->samples[k].index, one.samples[k].index);
      EXPECT_EQ(other->samples[k].before, one.samples[k].before); // exact: doubles compared bit for bit
      EXPECT_EQ(other->samples[k].after, one.samples[k].after);
    }
  }
  const auto s1 = pipeline::summarise(one), s2 = pipeline::summarise(merged);
  for (size_t i = 0; i < s1.names.size(); ++i) {
    EXPECT_EQ(s1.after[i].median, s2.after[i].median);
    EXPECT_EQ(s1.after[i].low, s2.after[i].low);
    EXPECT_EQ(s1.after[i].high, s2.after[i].high);
  }
  // Missing and doubled shards are refused.
  EXPECT_THROW(pipeline::summarise(pipeline::merge_runs({parts[0], parts[1]})), std::invalid_argument);
  EXPECT_THROW(pipeline::merge_runs({parts[0], parts[0]}), std::invalid_argument);
  o.shards = 1;
  o.shard = 1;
  o.seed = 43;
  EXPECT_NE(pipeline::run_monte_carlo(wb, table, o).samples[0].after, one.samples[0].after);
  std::filesystem::remove_all(dir);
}

// A broken partial file is an InputError at its line and field.
TEST(MonteCarlo, ABrokenPartialFileIsLocated) {
  const auto file = std::filesystem::temp_directory_path() / "geartopo_test_mc_broken.csv";
  {
    std::ofstream out(file);
    out << "# samples_total: 4\n# seed: 1\nsample,before.F_beta_um,after.F_beta_um\n0,1.5,0.5\n1,nan,0.5\n";
  }
  try {
    pipeline::read_run_csv(file);
    FAIL() << "nan accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(":5:3:"), std::string::npos) << m; // "1,nan,0.5": the value starts at character 3
    EXPECT_NE(m.find("before.F_beta_um"), std::string::npos) << m;
  }
  std::filesystem::remove(file);
}

// Issue 30: `merge` trusted what a shard said. A shard holds what compensate writes and nothing else: classes are whole
// numbers 1 … 11 (12: worse than 11), ISO values and the largest |deviation| are magnitudes (≥ 0), no µm value is
// beyond kMaxQuantityUm, and the seed fits 64 bits. Each refusal is located at the value (line:column) and says what
// is allowed. (The robustness corpus, shards/, holds one file per rule; these are the messages in full.)
TEST(MonteCarlo, APartialFileHoldsOnlyWhatCompensateCanWrite) {
  const auto file = std::filesystem::temp_directory_path() / ("geartopo_test_mc_rules_" + std::to_string(::getpid()) + ".csv");
  const auto error_of = [&](const std::string& head, const std::string& row) {
    std::ofstream(file) << head << "sample,before.F_alpha_um,before.F_alpha_class,before.thickness_um,after.F_alpha_um,"
                                   "after.F_alpha_class,after.thickness_um\n" << row << "\n";
    try {
      (void)pipeline::read_run_csv(file);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  const std::string head = "# samples_total: 2\n# seed: 3\n", f = file.string();
  EXPECT_EQ(error_of(head, "0,12.5,7,-1.5,3.25,4,0.5"), "(accepted)");
  EXPECT_EQ(error_of(head, "0,12.5,7,-1.5,3.25,99,0.5"),
            f + ":4:20: after.F_alpha_class: 99 is not a class of ISO 1328-1: a whole number of 1 … 11 (12: worse than class 11)");
  EXPECT_EQ(error_of(head, "0,12.5,12,-1.5,3.25,4,0.5"), "(accepted)"); // worse than class 11 is what the evaluation says
  EXPECT_EQ(error_of(head, "0,-12.5,7,-1.5,3.25,4,0.5"),
            f + ":4:3: before.F_alpha_um: -12.5 µm is negative: an ISO deviation or largest |deviation| is a magnitude, ≥ 0");
  EXPECT_EQ(error_of(head, "0,1e300,7,-1.5,3.25,4,0.5"),
            f + ":4:3: before.F_alpha_um: 1e300 µm is beyond ±10000 µm, more than a ground gear deviates (a wrong unit or "
                "an edited file)");
  EXPECT_EQ(error_of(head, "0,12.5,7,-1.5,3.25,4,-0.5"), "(accepted)"); // a thinner tooth is a signed value
  EXPECT_EQ(error_of(head, "2,12.5,7,-1.5,3.25,4,0.5"),
            f + ":4:1: sample: '2' is not a sample number of this run of 2 samples (0 … 1)");
  EXPECT_EQ(error_of("# samples_total: 2\n# seed: 18446744073709551616\n", "0,12.5,7,-1.5,3.25,4,0.5"),
            f + ":2:9: seed: '18446744073709551616' is not a seed: a whole number of 0 … 2⁶⁴ − 1");
  EXPECT_EQ(error_of("# samples_total: 2\n# seed: 18446744073709551615\n", "0,12.5,7,-1.5,3.25,4,0.5"), "(accepted)");
  std::filesystem::remove(file);
}

// The scene fingerprint: written by compensate, read back, compared by merge (which names the files). It changes with
// the scene file's bytes and with the settings behind the corrections, and with nothing else.
TEST(MonteCarlo, ShardsOfAnotherSceneDoNotMerge) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_mc_fingerprint_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "a.yaml") << mc_scene_text(""); }
  { std::ofstream(dir / "b.yaml") << mc_scene_text("") << "# the same scene with a comment\n"; }
  const workbench::Workbench a(dir / "a.yaml"), a_again(dir / "a.yaml"), b(dir / "b.yaml");
  const std::string fa = pipeline::scene_fingerprint(a, "method=flank step_mm=5");
  EXPECT_EQ(fa.size(), 16u);
  EXPECT_EQ(fa, pipeline::scene_fingerprint(a_again, "method=flank step_mm=5"));
  EXPECT_NE(fa, pipeline::scene_fingerprint(b, "method=flank step_mm=5"));
  EXPECT_NE(fa, pipeline::scene_fingerprint(a, "method=paper step_mm=5"));

  pipeline::MonteCarloRun one;
  one.samples_total = 2;
  one.seed = 9;
  one.names = {"F_alpha_um"};
  one.samples = {{0, {1.0}, {0.5}, {}}};
  one.scene_fingerprint = fa;
  pipeline::MonteCarloRun two = one;
  two.samples = {{1, {1.25}, {0.75}, {}}};
  two.scene_fingerprint = pipeline::scene_fingerprint(b, "method=flank step_mm=5");
  pipeline::write_run_csv(dir / "one.csv", one);
  pipeline::write_run_csv(dir / "two.csv", two);
  const auto r1 = pipeline::read_run_csv(dir / "one.csv"), r2 = pipeline::read_run_csv(dir / "two.csv");
  EXPECT_EQ(r1.scene_fingerprint, fa);
  try {
    (void)pipeline::merge_runs({r1, r2});
    ADD_FAILURE() << "shards of two scenes merged";
  } catch (const InputError& e) { // located at the part's line, as every reader's error
    // write_run_csv's lines: the title, samples_total, seed, the ISO words, probe noise, sampling (5 lines), then the
    // fingerprint on line 12
    EXPECT_EQ(std::string(e.what()),
              fmt::format("{}:12: scene_fingerprint: {} ({}:12: {}): computed from another scene, error table or "
                          "compensation setting",
                          (dir / "two.csv").string(), two.scene_fingerprint, (dir / "one.csv").string(), fa));
  }
  two.scene_fingerprint = fa;
  pipeline::write_run_csv(dir / "two.csv", two);
  EXPECT_EQ(pipeline::merge_runs({r1, pipeline::read_run_csv(dir / "two.csv")}).samples.size(), 2u);
  std::filesystem::remove_all(dir);
}

// Issue 43: a shard of another run is refused at its first differing line, with the field and the first part's line
// beside it; a setting the shard lacks is named at its header (before which it would stand). In memory: the part.
TEST(MonteCarlo, MergeNamesTheFirstDifferingSettingByFileLineAndField) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_mc_merge_lines_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  pipeline::MonteCarloRun one;
  one.samples_total = 2;
  one.seed = 9;
  one.names = {"F_alpha_um"};
  one.samples = {{0, {1.0}, {0.5}, {}}};
  one.gear = "teeth=35 normal_module_mm=14";
  pipeline::MonteCarloRun two = one;
  two.samples = {{1, {1.25}, {0.75}, {}}};
  two.seed = 10;          // line 3
  two.probe_noise_um = 1; // line 6: not the first difference
  pipeline::write_run_csv(dir / "one.csv", one);
  pipeline::write_run_csv(dir / "two.csv", two);
  const auto message = [](const std::vector<pipeline::MonteCarloRun>& parts) {
    try {
      (void)pipeline::merge_runs(parts);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("(merged)");
  };
  const auto a = (dir / "one.csv").string(), b = (dir / "two.csv").string();
  const auto r1 = pipeline::read_run_csv(dir / "one.csv");
  EXPECT_EQ(message({r1, pipeline::read_run_csv(dir / "two.csv")}),
            fmt::format("{}:3: seed: 10 ({}:3: 9): not the same run", b, a));
  try {
    (void)pipeline::merge_runs({r1, pipeline::read_run_csv(dir / "two.csv")});
  } catch (const InputError& e) { // located as every reader's error: the CLI prints it as such
    EXPECT_EQ(e.file(), b);
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "seed");
  }
  two.seed = one.seed;
  pipeline::write_run_csv(dir / "two.csv", two);
  EXPECT_EQ(message({r1, pipeline::read_run_csv(dir / "two.csv")}),
            fmt::format("{}:6: probe_noise_um: 1 µm ({}:6: 0 µm): not the same run", b, a));
  two.probe_noise_um = one.probe_noise_um;
  two.gear.clear(); // no "# gear:" line: the header (line 12) is where it would stand
  pipeline::write_run_csv(dir / "two.csv", two);
  EXPECT_EQ(message({r1, pipeline::read_run_csv(dir / "two.csv")}),
            fmt::format("{}:12: gear: not recorded ({}:12: teeth=35 normal_module_mm=14): not the same gear", b, a));
  two.gear = one.gear;
  two.names = {"F_beta_um"}; // the header, line 13
  for (auto& smp : two.samples) smp = {1, {1.25}, {0.75}, {}};
  pipeline::write_run_csv(dir / "two.csv", two);
  EXPECT_EQ(message({r1, pipeline::read_run_csv(dir / "two.csv")}),
            fmt::format("{}:13: header: F_beta_um ({}:13: F_alpha_um): other quantities (another scene?)", b, a));
  // Computed in memory: no file to name, the part and the field.
  two.names = one.names;
  two.seed = 11;
  EXPECT_EQ(message({one, two}), "part 2: seed: 11 (part 1: 9): not the same run");
  std::filesystem::remove_all(dir);
}

// The adaptive stop (JCGM 101:2008 §7.9.4, adapted): the statistic written out in the test — per batch of 100 the
// 95 % interval [y_(3), y_(98)] (q = 95, M − q = 5 odd → r = 3) and the median (y_(50) + y_(51))/2, then
// 2s = 2·√(Σ (x_r − x̄)² / (h(h − 1))) over the h batches — compared with adaptive_stability; classes are ignored.
TEST(MonteCarloAdaptive, TheStabilityStatisticIsTwiceTheStandardDeviationOfTheBatchMeans) {
  constexpr long long kBatch = 100, kBatches = 6;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> before(2.0, 0.7), after(1.0, 0.3);
  pipeline::MonteCarloRun run;
  run.names = {"F_p_um", "overall_class"};
  run.samples_total = kBatch * kBatches;
  for (long long k = 0; k < run.samples_total; ++k)
    run.samples.push_back({k, {before(rng), static_cast<double>(k % 7)}, {after(rng), static_cast<double>(k % 5)}, {}});
  double worst = 0.0;
  for (const bool is_after : {false, true})
    for (int what = 0; what < 3; ++what) { // median, low, high
      std::vector<double> per_batch;
      for (long long r = 0; r < kBatches; ++r) {
        std::vector<double> y;
        for (long long k = r * kBatch; k < (r + 1) * kBatch; ++k)
          y.push_back(is_after ? run.samples[static_cast<size_t>(k)].after[0] : run.samples[static_cast<size_t>(k)].before[0]);
        std::sort(y.begin(), y.end());
        per_batch.push_back(what == 0 ? 0.5 * (y[49] + y[50]) : what == 1 ? y[2] : y[97]);
      }
      double mean = 0.0, ss = 0.0;
      for (double x : per_batch) mean += x / kBatches;
      for (double x : per_batch) ss += (x - mean) * (x - mean);
      worst = std::max(worst, 2.0 * std::sqrt(ss / (kBatches * (kBatches - 1.0))));
    }
  const auto st = pipeline::adaptive_stability(run, kBatch, 1.0);
  EXPECT_EQ(st.batches, kBatches);
  EXPECT_NEAR(st.worst_two_s_um, worst, 1e-12);
  EXPECT_EQ(st.worst.rfind("before.F_p_um", 0), 0u) << st.worst << ": the wider distribution is the less stable";
  EXPECT_TRUE(pipeline::adaptive_stability(run, kBatch, worst * 1.0001).stable);
  EXPECT_FALSE(pipeline::adaptive_stability(run, kBatch, worst * 0.9999).stable);
  run.samples.pop_back();
  EXPECT_THROW(pipeline::adaptive_stability(run, kBatch, 1.0), std::invalid_argument);
}

// A C zero-position error of standard uncertainty u alone: the rotation line is N(0, σ²), σ = r_b cos β_b u (see
// UncertainCIndexIsANormallyDistributedRigidRotation). The adaptive run stops at a whole number of batches, equals
// the plain run of that many samples, does not depend on the threads, and its interval ends lie within three
// standard errors of ±1.96 σ (order statistics of M samples: √(p(1 − p)/M)/φ(1.96) σ).
TEST(MonteCarloAdaptive, StopsReproduciblyAndItsIntervalIsTheNormalOne) {
  const workbench::Workbench wb(scene::parse_scene(mc_scene_text(kOnlyCIndexUncertain), "mem"));
  const double sigma_um = rotation_sd_um(20.0);
  const auto table = nominal_corrections(wb);
  pipeline::MonteCarloOptions o;
  o.seed = 11;
  o.adaptive_tolerance_um = 0.3;
  o.adaptive_batch = 50;
  o.adaptive_max_samples = 2000;
  o.threads = 1;
  const auto one = pipeline::run_monte_carlo(wb, table, o);
  o.threads = 2;
  const auto two = pipeline::run_monte_carlo(wb, table, o);
  const auto m = static_cast<long long>(one.samples.size());
  ASSERT_EQ(m % 50, 0);
  ASSERT_GE(m, 100);
  ASSERT_LT(m, 2000) << "did not stabilise";
  EXPECT_EQ(one.samples_total, m);
  EXPECT_TRUE(pipeline::adaptive_stability(one, 50, 0.3).stable);
  if (m > 100) { // it did not stop one batch earlier
    pipeline::MonteCarloRun shorter = one;
    shorter.samples.resize(static_cast<size_t>(m - 50));
    EXPECT_FALSE(pipeline::adaptive_stability(shorter, 50, 0.3).stable);
  }
  pipeline::MonteCarloOptions plain;
  plain.seed = 11;
  plain.samples = m;
  const auto reference = pipeline::run_monte_carlo(wb, table, plain);
  for (const auto* other : {&two, &reference}) {
    ASSERT_EQ(other->samples.size(), one.samples.size());
    for (size_t k = 0; k < one.samples.size(); ++k) {
      EXPECT_EQ(other->samples[k].before, one.samples[k].before);
      EXPECT_EQ(other->samples[k].after, one.samples[k].after);
    }
  }
  const auto s = pipeline::summarise(one);
  const double se_end = std::sqrt(0.025 * 0.975 / static_cast<double>(m)) / 0.05844 * sigma_um;
  for (const auto* side : {&s.before, &s.after}) {
    const auto& rot = (*side)[static_cast<size_t>(s.find("rotation_um"))];
    EXPECT_NEAR(rot.low, -1.96 * sigma_um, 3 * se_end);
    EXPECT_NEAR(rot.high, 1.96 * sigma_um, 3 * se_end);
  }
  // The maximum holds: a tolerance no run meets stops at the largest whole number of batches within it.
  o.adaptive_tolerance_um = 1e-9;
  o.adaptive_max_samples = 120;
  EXPECT_EQ(pipeline::run_monte_carlo(wb, table, o).samples.size(), 100u);
  o.shards = 2; // the stop depends on all samples: no shards
  EXPECT_THROW(pipeline::run_monte_carlo(wb, table, o), std::invalid_argument);
}

namespace {

std::string slurp_mc(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// stdout (and stderr, unless `err` names a file of its own: mixed, stderr's unbuffered lines can land inside a line of
/// stdout's) into `log`.
int run_geartopo(const std::string& args, const std::filesystem::path& log, const std::filesystem::path& err = {}) {
  const std::string to_err = err.empty() ? std::string(" 2>&1") : " 2>" + err.string();
  const int status = std::system((std::string(GEARTOPO_BINARY) + " " + args + " >" + log.string() + to_err).c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

} // namespace

// The scale-out recipe end to end: `compensate --shard 1/2` and `2/2`, then `merge`, give the very bytes of one run's
// prediction.json and prediction_samples.csv.
TEST(MonteCarloCli, MergedShardsEqualOneRunByteForByte) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_mc_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "scene.yaml") << mc_scene_text(kMapErrors); }
  const std::string scene = (dir / "scene.yaml").string(), log = (dir / "log.txt").string();
  const std::string common = " --samples 6 --seed 5 --step 5";
  ASSERT_EQ(run_geartopo("compensate " + scene + " --out " + (dir / "one").string() + common, log), 0) << slurp_mc(log);
  EXPECT_NE(slurp_mc(log).find("95 % interval"), std::string::npos) << slurp_mc(log);
  for (int i : {1, 2})
    ASSERT_EQ(run_geartopo("compensate " + scene + " --out " + (dir / ("s" + std::to_string(i))).string() + common +
                               " --shard " + std::to_string(i) + "/2", log), 0)
        << slurp_mc(log);
  EXPECT_FALSE(std::filesystem::exists(dir / "s1" / "prediction.json")); // a shard has no summary of its own
  ASSERT_EQ(run_geartopo("merge " + (dir / "s2" / "prediction_samples.csv").string() + " " +
                             (dir / "s1" / "prediction_samples.csv").string() + " --out " + (dir / "merged").string(), log), 0)
      << slurp_mc(log);
  for (const char* f : {"prediction.json", "prediction_samples.csv", "prediction.txt"}) {
    const std::string a = slurp_mc(dir / "one" / f), b = slurp_mc(dir / "merged" / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, b) << f;
  }
  // One shard alone is not a result; a shard beyond n is bad usage.
  EXPECT_EQ(run_geartopo("merge " + (dir / "s1" / "prediction_samples.csv").string() + " --out " + (dir / "m2").string(), log), 1);
  EXPECT_NE(slurp_mc(log).find("merge every shard"), std::string::npos) << slurp_mc(log);
  EXPECT_EQ(run_geartopo("compensate " + scene + " --out " + (dir / "bad").string() + common + " --shard 3/2", log), 2);
  EXPECT_NE(slurp_mc(log).find("--shard"), std::string::npos) << slurp_mc(log);
  std::filesystem::remove_all(dir);
}

// A Slurm array job (docs/monte-carlo.md, "Slurm array job"): without --shard, each task's shard comes from
// SLURM_ARRAY_TASK_ID − SLURM_ARRAY_TASK_MIN + 1 of SLURM_ARRAY_TASK_COUNT, said on stderr; the tasks of a 0-based
// array (--array=0-1) merged give the bytes of one run without the variables (the truth: a run that knows no Slurm).
// An explicit --shard wins; an array with a step (tasks 1, 3, 5: the ID is not the place) is refused naming --shard.
TEST(MonteCarloCli, ASlurmArrayTaskTakesItsShardFromTheEnvironment) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_mc_slurm_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "scene.yaml") << mc_scene_text(kMapErrors); }
  const std::string scene = (dir / "scene.yaml").string(), log = (dir / "log.txt").string();
  const std::string common = " --samples 6 --seed 5 --step 5";
  const auto slurm = [](int id, int min, int max, int count) {
    return "env SLURM_ARRAY_TASK_ID=" + std::to_string(id) + " SLURM_ARRAY_TASK_MIN=" + std::to_string(min) +
           " SLURM_ARRAY_TASK_MAX=" + std::to_string(max) + " SLURM_ARRAY_TASK_COUNT=" + std::to_string(count) + " ";
  };
  const auto run_env = [&](const std::string& env, const std::string& args) {
    const int status = std::system((env + GEARTOPO_BINARY + " " + args + " >" + log + " 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  ASSERT_EQ(run_env("env -u SLURM_ARRAY_TASK_ID ", "compensate " + scene + " --out " + (dir / "one").string() + common), 0)
      << slurp_mc(log);
  for (int id : {0, 1}) {
    ASSERT_EQ(run_env(slurm(id, 0, 1, 2), "compensate " + scene + " --out " + (dir / ("t" + std::to_string(id))).string() + common), 0)
        << slurp_mc(log);
    EXPECT_NE(slurp_mc(log).find(fmt::format("--shard {}/2 from the Slurm array job", id + 1)), std::string::npos) << slurp_mc(log);
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "t0" / "prediction.json")); // a shard
  ASSERT_EQ(run_geartopo("merge " + (dir / "t0" / "prediction_samples.csv").string() + " " +
                             (dir / "t1" / "prediction_samples.csv").string() + " --out " + (dir / "merged").string(), log), 0)
      << slurp_mc(log);
  for (const char* f : {"prediction.json", "prediction_samples.csv", "prediction.txt"})
    EXPECT_EQ(slurp_mc(dir / "one" / f), slurp_mc(dir / "merged" / f)) << f;
  // --shard given: the environment is not read.
  ASSERT_EQ(run_env(slurm(0, 0, 1, 2), "compensate " + scene + " --out " + (dir / "given").string() + common + " --shard 1/1"), 0)
      << slurp_mc(log);
  EXPECT_EQ(slurp_mc(log).find("Slurm"), std::string::npos) << slurp_mc(log);
  EXPECT_EQ(slurp_mc(dir / "one" / "prediction.json"), slurp_mc(dir / "given" / "prediction.json"));
  // --array=1-5:2 (tasks 1, 3, 5): refused.
  EXPECT_EQ(run_env(slurm(3, 1, 5, 3), "compensate " + scene + " --out " + (dir / "step").string() + common), 2);
  EXPECT_NE(slurp_mc(log).find("--shard"), std::string::npos) << slurp_mc(log);
  EXPECT_FALSE(std::filesystem::exists(dir / "step"));
  std::filesystem::remove_all(dir);
}

// What limits the default gear after compensation, from arithmetic on the scene's numbers (docs/monte-carlo.md, "What
// limits the gear after compensation"): with the default scene's 0.1 µm / 0.1 mdeg resolution the held axes' steps
// (X, Y, A: C and Z, which the stroke sweeps, average out) are 0.1 µm and 1.75 µrad, tenths of a µm on the flanks,
// while each stroke's C scatters by s = 0.25 mdeg = 4.4 µrad, 1.0 µm on the flanks (r_b cos β_b = 230 mm), and X, Y, Z
// by 0.75 µm: the repeatability sets the pitch and the class. With X and Y in steps of 5 µm — their corrections vary by
// 4–6 µm along a stroke, so they step by 5 µm somewhere along most strokes, up to 5 µm on the flanks, five times the
// stroke scatter — the rounding sets the class, the gear is worse than without compensation, and the warning names
// the rounding with the class measured without it.
TEST(MonteCarloCli, TheMainJobNamesWhatLimitsTheClassAfterCompensation) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_mc_limit_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string source_dir = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/";
  std::string text = slurp_mc(source_dir + "skmc1200w-mn14-z35.yaml");
  for (size_t at = text.find("machine/"); at != std::string::npos; at = text.find("machine/", at + source_dir.size() + 8))
    text.insert(at, source_dir);
  text.replace(text.find("demo/measured.csv"), 0, source_dir);
  const std::string fine = "resolution: {x_um: 0.1, y_um: 0.1, z_um: 0.1, a_mdeg: 0.1, c_mdeg: 0.1}";
  ASSERT_NE(text.find(fine), std::string::npos) << "the default scene states its controller's resolution";
  { std::ofstream(dir / "fine.yaml") << text; }
  std::string coarse = text;
  coarse.replace(coarse.find(fine), fine.size(), "resolution: {x_um: 5, y_um: 5, z_um: 1, a_mdeg: 1, c_mdeg: 1}");
  { std::ofstream(dir / "coarse.yaml") << coarse; }
  const std::string log = (dir / "log.txt").string();
  ASSERT_EQ(run_geartopo("compensate " + (dir / "fine.yaml").string() + " --out " + (dir / "fine").string() + " --samples 40", log), 0)
      << slurp_mc(log);
  const auto fine_json = nlohmann::json::parse(slurp_mc(dir / "fine" / "prediction.json"));
  EXPECT_EQ(fine_json["sampling"]["method"], "linear");
  EXPECT_EQ(fine_json["limit"]["dominant"], "repeatability") << fine_json["limit"].dump(1);
  EXPECT_NE(slurp_mc(log).find("limit after compensation: the repeatability"), std::string::npos) << slurp_mc(log);
  const std::string err = (dir / "err.txt").string();
  ASSERT_EQ(run_geartopo("compensate " + (dir / "coarse.yaml").string() + " --out " + (dir / "coarse").string() + " --samples 40", log, err), 0)
      << slurp_mc(log) << slurp_mc(err);
  const auto coarse_json = nlohmann::json::parse(slurp_mc(dir / "coarse" / "prediction.json"));
  EXPECT_EQ(coarse_json["limit"]["dominant"], "resolution_rounding") << coarse_json["limit"].dump(1);
  const auto& q = coarse_json["quantities"]["overall_class"];
  EXPECT_GT(q["after"]["median"].get<double>(), q["before"]["median"].get<double>()) << "the 5 µm steps make it worse";
  const double without = coarse_json["limit"]["without"]["resolution_rounding"]["overall_class"].get<double>();
  EXPECT_LT(without, q["after"]["median"].get<double>());
  EXPECT_NE(slurp_mc(err).find(fmt::format("without the rounding to machine.resolution the median class is {:g}", without)),
            std::string::npos)
      << slurp_mc(err);
  // Each size predicted worse names its cause (iso1328.json improvement.…worse, the same sentence on stdout): the
  // source without which its after-median falls most, recomputed here from the prediction's decomposition; a size
  // not worse has none.
  const auto iso = nlohmann::json::parse(slurp_mc(dir / "coarse" / "iso1328.json"));
  int worse_sizes = 0;
  for (const auto& [name, imp] : iso["improvement"]["quantities"].items()) {
    const auto& band = coarse_json["quantities"][name];
    const bool worse = band["after"]["median"].get<double>() > band["before"]["median"].get<double>();
    ASSERT_EQ(worse, imp.contains("worse")) << name;
    if (!worse) continue;
    ++worse_sizes;
    std::string best;
    double best_median = 0.0;
    for (const auto& [source, w] : coarse_json["limit"]["without"].items()) {
      const double m = w["quantities"][name]["median"].get<double>();
      if (best.empty() || m < best_median) best = source, best_median = m;
    }
    EXPECT_EQ(imp["worse"]["source"], best) << name;
    if (name == "f_falpha_um" || name == "f_fbeta_um") {
      EXPECT_EQ(imp["worse"]["source"], "resolution_rounding") << name;
    }
    EXPECT_NEAR(imp["worse"]["after_median_without_source_um"].get<double>(), best_median, 1e-12) << name;
    EXPECT_NE(slurp_mc(log).find(imp["worse"]["text"].get<std::string>()), std::string::npos) << name;
  }
  EXPECT_TRUE(iso["improvement"]["quantities"]["f_falpha_um"].contains("worse")) << "X's and Y's 5 µm steps";
  EXPECT_TRUE(iso["improvement"]["quantities"]["f_fbeta_um"].contains("worse")) << "X's and Y's 5 µm steps";
  std::filesystem::remove_all(dir);
}

// The closed loop (docs/tutorial.md, "6."): the truth machine is one machine within the scene's stated uncertainties —
// every one of the 43 components of the scene's map shifted by a draw of N(0, u²), each stroke off by the axes'
// repeatability — drawn here with the standard library's generator, plus a thermal drift the scene does not model.
// Gear 1 is measured on it; diagnosis (generalised least squares with the scene's declared scatter and map
// uncertainty) names the drift; the corrections are computed on the scene with the identified effect, its values
// carried with their standard uncertainties and correlation; Monte Carlo predicts gear 2; gear 2 ground on the truth
// machine with those corrections (rounded to the resolution, as the controller takes them) lies inside the predicted
// 95 % intervals and is better than gear 1. Measured (gear 1's probe noise from synth's SplitMix64, seed 4):
// x_growth 26.0 ± 7.4 µm, z_growth 1.2 ± 3.0 µm, τ 124 ± 77 s (truth 25, 0, 120); gear 2 f_p 2.61 µm in [2.30, 5.70],
// F_p 4.91 in [4.47, 17.9], largest 11.6 in [4.0, 15.9] µm; gear 1 largest 24.1 µm. One truth, one measurement: with
// seed 3 (the seed before synth's generator was SplitMix64) gear 2's f_p, 2.43 µm, lies 0.03 µm below its band
// [2.46, 6.47] — five 95 % intervals all hold for about 4 in 5 such truths, so a seed is a draw, not a proof.
TEST(MonteCarloClosedLoop, Gear2FromTheTruthFallsInsideThePredictionAndIsBetter) {
  const workbench::Workbench model(scene::parse_scene(mc_scene_text(kMapErrors), "model"));
  const auto& u = model.scene.machine.uncertainty; // the documented defaults (checked above)
  std::mt19937_64 gen(2026);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::string truth_constants = "  constants: {";
  for (int k = 0; k < machine::kComponentCount; ++k) {
    const auto id = machine::component_at(k);
    const auto& info = machine::info(id);
    const bool length = info.quantity == machine::Quantity::Length;
    const double nominal = model.machine.source(id).value(0.0); // the scene's map holds constants only
    const double v = nominal + u.component_u[static_cast<size_t>(k)] * normal(gen);
    truth_constants += fmt::format("{}{}_{}: {}", k ? ", " : "", info.name, length ? "um" : "urad", (length ? 1e3 : 1e6) * v);
  }
  truth_constants += "}\n";
  const std::string hidden = "effects:\n  - {type: thermal_drift, x_growth_um: 25, time_constant_s: 120}\n";
  const workbench::Workbench truth(scene::parse_scene(mc_scene_text(truth_constants) + hidden, "truth"));
  // Each gear's strokes: command offsets of N(0, s²) per space and axis, s = R/4 of the scene.
  const auto with_repeatability = [&](const compensation::CorrectionTable& t) {
    std::set<int> spaces;
    for (const auto& r : t.rows()) spaces.insert(r.space);
    return pipeline::with_stroke_offsets(
        t, pipeline::draw_stroke_offsets(spaces, u.repeatability, [&] { return normal(gen); }));
  };
  const auto nominal_rows = nominal_corrections(model).rows();
  std::vector<compensation::CorrectionRow> zero_rows = nominal_rows;
  for (auto& r : zero_rows) r.correction.setZero();
  const auto gear1_table = with_repeatability(compensation::CorrectionTable(zero_rows));
  const compensation::CompensatedProcess gear1_process(truth.process(), gear1_table);

  diagnosis::SynthOptions so;
  so.teeth = {1, 3, 5, 7, 9, 11, 13, 15, 17, 19};
  so.rows = 5;
  so.cols = 5;
  so.noise_um = 0.3;
  so.seed = 4;
  const auto gear1_points =
      measurement::measured_points(diagnosis::synthesize(truth.setup, gear1_process, so), model.setup.geometry(), "gear1");
  diagnosis::DiagnoseOptions dopt;
  dopt.noise_um = so.noise_um;
  // What the scene declares the residual carries besides probe noise: each stroke's scatter and the map's uncertainty.
  // Diagnosis fits by generalised least squares with that covariance (docs/diagnosis.md); fitted as white noise, the
  // drift took up both (τ 60 ± 3 s for the true 120 s, z growth 10.2 ± 0.5 µm for the true 0) and gear 2's f_p fell
  // outside its predicted interval.
  dopt.stroke_repeatability_sd = u.repeatability;
  dopt.model_uncertainty_um = diagnosis::map_sensitivity(model, gear1_points);
  const auto d = diagnosis::diagnose(model.setup, model.process(), gear1_points, model.effect_types(), dopt);
  ASSERT_TRUE(d.chosen) << d.verdict;
  // The drift is named; a second effect may come with it, taking up part of the map's deviation from the scene.
  ASSERT_NE(d.chosen->name().find("thermal_drift"), std::string::npos) << d.verdict;
  // The scatter and the map's deviation the scene declares are not "more than noise" (false alarm 0.001).
  EXPECT_EQ(d.verdict.find("more than noise"), std::string::npos) << d.verdict;

  // The fit's standard uncertainties go with the values, and their correlation, so that amplitude and time constant
  // are drawn as the fit allows them together: the prediction carries what the measurement left open (what
  // `diagnose` writes into scene_with_effect.yaml).
  const auto found = diagnosis::identified_effects(d, *d.chosen);
  std::cout << "Birge ratio " << found.birge_ratio << "\n" << d.verdict << "\n";
  for (const auto& ps : d.chosen->parameters)
    for (const auto& p : ps) std::cout << p.key << " = " << p.value << " ± " << p.uncertainty << "\n";
  std::cout << "correlation\n" << d.chosen->correlation << "\n";
  scene::Scene identified = model.scene;
  identified.effects = found.effects;
  identified.effect_uncertainties = found.uncertainties;
  identified.effect_correlation = found.correlation;
  const workbench::Workbench wb(std::move(identified));
  const auto table = nominal_corrections(wb);
  pipeline::MonteCarloOptions o;
  o.samples = 100;
  o.seed = 11;
  const auto predicted = pipeline::summarise(pipeline::run_monte_carlo(wb, table, o));

  const auto gear2_table = with_repeatability(pipeline::rounded_to_resolution(table, wb.scene.machine.uncertainty.resolution));
  const compensation::CompensatedProcess gear2_process(truth.process(), gear2_table);
  const auto& g = truth.setup.geometry();
  const auto topo1 = grinding::simulate_topology(truth.setup, gear1_process, grid_of(truth));
  const auto topo2 = grinding::simulate_topology(truth.setup, gear2_process, grid_of(truth));
  const auto gear1 = pipeline::gear_quantities(workbench::evaluate_iso(g, truth.setup.ranges(), topo1), topo1);
  const auto gear2 = pipeline::gear_quantities(workbench::evaluate_iso(g, truth.setup.ranges(), topo2), topo2);
  for (const char* name : {"F_alpha_um", "F_beta_um", "f_p_um", "F_p_um", "largest_abs_um"}) {
    const int i = predicted.find(name);
    ASSERT_GE(i, 0) << name;
    const auto& band = predicted.after[static_cast<size_t>(i)];
    const double v = value_of(gear2, name);
    EXPECT_GE(v, band.low) << name;
    EXPECT_LE(v, band.high) << name;
    std::cout << name << ": gear 1 " << value_of(gear1, name) << ", gear 2 " << v << " µm, predicted " << band.median
              << " [" << band.low << ", " << band.high << "]\n";
  }
  EXPECT_LT(value_of(gear2, "largest_abs_um"), value_of(gear1, "largest_abs_um"));
  EXPECT_LT(value_of(gear2, "F_p_um"), value_of(gear1, "F_p_um"));
}

namespace {

/// ISO 1328-1 total and form deviation of one trace over its evaluation range [s, e], from the definitions written
/// out here: the trace is the polyline through (x_i, y_i) cut to [s, e] (end values interpolated); the total
/// deviation is its range; the form deviation is the range of its residuals about its least-squares line over
/// [s, e], the line found here by fitting 200 evenly spaced samples per segment of the polyline (a discrete
/// approximation of the continuous fit, independent of the library's closed-form integrals).
std::pair<double, double> total_and_form_um(const std::vector<double>& x, const std::vector<double>& y, double s, double e) {
  const auto at = [&](double v) {
    for (size_t i = 1; i < x.size(); ++i)
      if (x[i] >= v) return y[i - 1] + (v - x[i - 1]) / (x[i] - x[i - 1]) * (y[i] - y[i - 1]);
    return y.back();
  };
  std::vector<double> u{s}, w{at(s)};
  for (size_t i = 0; i < x.size(); ++i)
    if (x[i] > s && x[i] < e) u.push_back(x[i]), w.push_back(y[i]);
  u.push_back(e), w.push_back(at(e));
  double su = 0, sw = 0, suu = 0, suw = 0, n = 0;
  for (size_t i = 1; i < u.size(); ++i)
    for (int k = 0; k < 200; ++k) {
      const double t = (k + 0.5) / 200.0, uu = u[i - 1] + t * (u[i] - u[i - 1]), ww = w[i - 1] + t * (w[i] - w[i - 1]);
      const double weight = u[i] - u[i - 1]; // samples per unit length alike on every segment
      su += weight * uu, sw += weight * ww, suu += weight * uu * uu, suw += weight * uu * ww, n += weight;
    }
  const double b = (n * suw - su * sw) / (n * suu - su * su), a = (sw - b * su) / n;
  double wmin = w[0], wmax = w[0], rmin = 1e300, rmax = -1e300;
  for (size_t i = 0; i < u.size(); ++i) {
    wmin = std::min(wmin, w[i]), wmax = std::max(wmax, w[i]);
    const double r = w[i] - (a + b * u[i]);
    rmin = std::min(rmin, r), rmax = std::max(rmax, r);
  }
  return {wmax - wmin, rmax - rmin};
}

double quantile_of(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5)];
}

} // namespace

// Probe noise in the prediction: on a perfect machine (no errors, nothing uncertain, no repeatability or resolution)
// both gears are exactly involute, so with probe noise σ every helix trace is n = 15 independent N(0, σ²) deviates at
// its points (evenly over the face width, as the scene lays them), and F_β and f_fβ of a gear are the largest over its
// 2z = 40 flanks of the trace's total and form deviation over L_β. The truth: the same statistic from the
// definitions (total_and_form_um) on 4000 gears drawn here with the standard library's generator. The Monte Carlo's
// median of 200 samples must lie within three standard errors of the truth's median; the standard error of a sample
// median, √(1/4M)/f(m), with the density f(m) at the median read off the truth's own quantiles
// (0.1/(q(0.55) − q(0.45))), for both (the truth's own error included). Values in the normal direction
// (--iso-direction normal): the noise is along the flank normal.
TEST(MonteCarloProbeNoise, APerfectMachineMeasuredWithNoiseGivesTheNoisesHelixDeviations) {
  constexpr double kSigmaUm = 0.5;
  const workbench::Workbench wb(scene::parse_scene(mc_scene_text(kNothingUncertain), "mem"));
  const auto table = nominal_corrections(wb);
  pipeline::MonteCarloOptions o;
  o.samples = 200;
  o.seed = 3;
  o.iso.direction = evaluation::IsoDirection::Normal;
  const auto quiet = pipeline::summarise(pipeline::run_monte_carlo(wb, table, o));
  ASSERT_LT(quiet.before[static_cast<size_t>(quiet.find("F_beta_um"))].high, 1e-6) << "the machine is not perfect";
  o.probe_noise_um = kSigmaUm;
  const auto noisy = pipeline::summarise(pipeline::run_monte_carlo(wb, table, o));
  EXPECT_EQ(noisy.probe_noise_um, kSigmaUm);

  const auto& r = wb.setup.ranges();
  const double b = wb.setup.geometry().spec().face_width_mm;
  std::vector<double> z;
  for (int i = 0; i < 15; ++i) z.push_back(b * i / 14.0); // 15 helix points evenly over the face width
  std::mt19937_64 gen(2024);
  std::normal_distribution<double> normal(0.0, kSigmaUm);
  std::vector<double> total, form;
  for (int gear = 0; gear < 4000; ++gear) {
    double worst_total = 0, worst_form = 0;
    for (int flank = 0; flank < 40; ++flank) {
      std::vector<double> y;
      for (size_t i = 0; i < z.size(); ++i) y.push_back(normal(gen));
      const auto [t, f] = total_and_form_um(z, y, r.z_eval_start_mm, r.z_eval_end_mm);
      worst_total = std::max(worst_total, t), worst_form = std::max(worst_form, f);
    }
    total.push_back(worst_total), form.push_back(worst_form);
  }
  for (const auto& [name, truth] : {std::pair{"F_beta_um", &total}, {"f_fbeta_um", &form}}) {
    const double median = quantile_of(*truth, 0.5);
    const double density = 0.1 / (quantile_of(*truth, 0.55) - quantile_of(*truth, 0.45));
    const double se = std::sqrt(0.25 / 200.0 + 0.25 / 4000.0) / density;
    for (const auto* side : {&noisy.before, &noisy.after})
      EXPECT_NEAR((*side)[static_cast<size_t>(noisy.find(name))].median, median, 3 * se) << name;
    std::cout << name << ": Monte Carlo median before " << noisy.before[static_cast<size_t>(noisy.find(name))].median
              << ", after " << noisy.after[static_cast<size_t>(noisy.find(name))].median << " µm; from the definition "
              << median << " ± " << se << " µm (one standard error)\n";
  }
}

// The probe draws from a stream of its own: with noise the samples stay the same at any thread count and shard (bit
// for bit), the partial file and the summary carry σ, and a merge refuses parts with another σ or other ISO options.
TEST(MonteCarloProbeNoise, NoisySamplesAreReproducibleAndRecorded) {
  const workbench::Workbench wb(scene::parse_scene(mc_scene_text(kMapErrors), "mem"));
  const auto table = nominal_corrections(wb);
  pipeline::MonteCarloOptions o;
  o.samples = 4;
  o.seed = 9;
  o.probe_noise_um = 0.2;
  o.iso.helix_slope_sign = evaluation::HelixSlopeSign::RiseTowardsPlusZ;
  o.threads = 1;
  const auto one = pipeline::run_monte_carlo(wb, table, o);
  o.threads = 2;
  o.shards = 2;
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_test_mc_noise_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::vector<pipeline::MonteCarloRun> parts;
  for (int i : {1, 2}) {
    o.shard = i;
    pipeline::write_run_csv(dir / "part.csv", pipeline::run_monte_carlo(wb, table, o));
    parts.push_back(pipeline::read_run_csv(dir / "part.csv"));
  }
  EXPECT_EQ(parts[0].probe_noise_um, 0.2);
  EXPECT_EQ(parts[0].iso.helix_slope_sign, evaluation::HelixSlopeSign::RiseTowardsPlusZ);
  const auto merged = pipeline::merge_runs(parts);
  ASSERT_EQ(merged.samples.size(), one.samples.size());
  for (size_t k = 0; k < one.samples.size(); ++k) {
    EXPECT_EQ(merged.samples[k].before, one.samples[k].before);
    EXPECT_EQ(merged.samples[k].after, one.samples[k].after);
  }
  // Noise changes the measured gears, not the machine's draws: with σ = 10⁻⁶ µm every µm quantity is within 10⁻⁴ µm
  // of the noise-free run of the same seed (a machine drawn anew would differ by µm), and F_β is not bit-equal to it.
  o.shards = o.shard = 1;
  o.probe_noise_um = 0.0;
  const auto quiet = pipeline::run_monte_carlo(wb, table, o);
  o.probe_noise_um = 1e-6;
  const auto tiny = pipeline::run_monte_carlo(wb, table, o);
  bool changed = false;
  for (size_t k = 0; k < quiet.samples.size(); ++k)
    for (size_t n = 0; n < quiet.names.size(); ++n) {
      if (!quiet.names[n].ends_with("_um")) continue;
      EXPECT_NEAR(tiny.samples[k].before[n], quiet.samples[k].before[n], 1e-4) << quiet.names[n];
      EXPECT_NEAR(tiny.samples[k].after[n], quiet.samples[k].after[n], 1e-4) << quiet.names[n];
      changed = changed || tiny.samples[k].after[n] != quiet.samples[k].after[n];
    }
  EXPECT_TRUE(changed) << "the noise was not applied";
  auto other_noise = parts[1];
  other_noise.probe_noise_um = 0.3;
  // Refused naming the first differing setting (file:line: field), not merged into one wrong distribution.
  try {
    pipeline::merge_runs({parts[0], other_noise});
    ADD_FAILURE() << "runs with another probe noise were merged";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("probe_noise_um: 0.3"), std::string::npos) << e.what();
  }
  auto other_iso = parts[1];
  other_iso.iso.direction = evaluation::IsoDirection::Normal;
  try {
    pipeline::merge_runs({parts[0], other_iso});
    ADD_FAILURE() << "runs with another ISO direction were merged";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("iso_direction: normal"), std::string::npos) << e.what();
  }
  // A partial file written before σ and the ISO options were recorded reads as 0, transverse, helix-angle.
  {
    std::ofstream out(dir / "old.csv");
    out << "# samples_total: 1\n# seed: 1\nsample,before.F_beta_um,after.F_beta_um\n0,1.5,0.5\n";
  }
  const auto old = pipeline::read_run_csv(dir / "old.csv");
  EXPECT_EQ(old.probe_noise_um, 0.0);
  EXPECT_EQ(old.iso.direction, evaluation::IsoDirection::Transverse);
  EXPECT_EQ(old.iso.helix_slope_sign, evaluation::HelixSlopeSign::HelixAngle);
  {
    std::ofstream out(dir / "bad.csv");
    out << "# samples_total: 1\n# seed: 1\n# iso_direction: sideways\nsample,before.F_beta_um,after.F_beta_um\n0,1.5,0.5\n";
  }
  try {
    pipeline::read_run_csv(dir / "bad.csv");
    ADD_FAILURE() << "sideways accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":3:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("iso_direction"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// Any block [first, last) of a run equals the same samples of the plain run (sample k depends on (seed, k) only):
// the adaptive batches and the MPI driver's blocks are such ranges.
TEST(MonteCarlo, ABlockOfSamplesEqualsTheSameSamplesOfTheRun) {
  const workbench::Workbench wb(scene::parse_scene(mc_scene_text(kMapErrors), "mem"));
  const auto table = nominal_corrections(wb);
  pipeline::MonteCarloOptions o;
  o.samples = 6;
  o.seed = 4;
  const auto whole = pipeline::run_monte_carlo(wb, table, o);
  const auto block = pipeline::run_monte_carlo_samples(wb, table, o, 2, 5);
  ASSERT_EQ(block.samples.size(), 3u);
  EXPECT_EQ(block.samples_total, 6);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(block.samples[i].index, static_cast<long long>(2 + i));
    EXPECT_EQ(block.samples[i].before, whole.samples[2 + i].before);
    EXPECT_EQ(block.samples[i].after, whole.samples[2 + i].after);
  }
  EXPECT_THROW(pipeline::run_monte_carlo_samples(wb, table, o, 4, 7), std::invalid_argument);
  EXPECT_THROW(pipeline::run_monte_carlo_samples(wb, table, o, 3, 2), std::invalid_argument);
}

// prediction.json records the ISO options its samples were evaluated with, and `evaluate --prediction` uses them.
// Truth for the options reaching the samples: ISO 1328-1's transverse values are the normal ones divided by cos β_b
// (β_b from the gear data, ISO 21771), so on a machine with nothing uncertain (every sample the nominal gear) the
// predicted F_α and F_β medians of a normal-direction run are those of a transverse run times cos β_b.
TEST(MonteCarloCli, PredictionRecordsItsIsoOptionsAndEvaluateUsesThem) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_mc_iso_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "scene.yaml") << mc_scene_text(kMapErrors + kNothingUncertain); }
  const std::string scene = (dir / "scene.yaml").string(), log = (dir / "log.txt").string();
  const std::string common = " --samples 2 --seed 5 --step 5";
  ASSERT_EQ(run_geartopo("compensate " + scene + " --out " + (dir / "t").string() + common, log), 0) << slurp_mc(log);
  ASSERT_EQ(run_geartopo("compensate " + scene + " --out " + (dir / "n").string() + common +
                             " --iso-direction normal --helix-slope-sign rise-towards-plus-z", log), 0)
      << slurp_mc(log);
  const auto t = nlohmann::json::parse(slurp_mc(dir / "t" / "prediction.json"));
  const auto n = nlohmann::json::parse(slurp_mc(dir / "n" / "prediction.json"));
  EXPECT_EQ(t["iso_options"]["iso_direction"], "transverse");
  EXPECT_EQ(t["iso_options"]["helix_slope_sign"], "helix-angle");
  EXPECT_EQ(n["iso_options"]["iso_direction"], "normal");
  EXPECT_EQ(n["iso_options"]["helix_slope_sign"], "rise-towards-plus-z");
  EXPECT_EQ(n["probe_noise_um"], 0.0);
  const double cos_beta_b = std::cos(std::asin(std::sin(20.0 * units::kRadPerDeg) * std::cos(20.0 * units::kRadPerDeg)));
  for (const char* q : {"F_alpha_um", "F_beta_um"}) {
    const double tv = t["quantities"][q]["before"]["median"], nv = n["quantities"][q]["before"]["median"];
    ASSERT_GT(tv, 0.1) << q; // the map errors give the gear a helix and profile deviation
    EXPECT_NEAR(nv, tv * cos_beta_b, 1e-6 * tv) << q;
  }
  // evaluate: the prediction's options by default, a contradicting flag refused (usage, nothing written), an agreeing
  // one accepted.
  const std::string traces = (dir / "n" / "traces_after.csv").string(), pred = (dir / "n" / "prediction.json").string();
  const std::string evaluate = "evaluate " + scene + " --traces " + traces + " --prediction " + pred + " --out ";
  ASSERT_EQ(run_geartopo(evaluate + (dir / "e1").string(), log), 0) << slurp_mc(log);
  const auto e1 = nlohmann::json::parse(slurp_mc(dir / "e1" / "iso1328.json"));
  EXPECT_EQ(e1["before"]["iso_direction"], "normal");
  EXPECT_EQ(e1["before"]["helix_slope_sign"], "rise-towards-plus-z");
  EXPECT_EQ(run_geartopo(evaluate + (dir / "e2").string() + " --iso-direction transverse", log), 2);
  EXPECT_NE(slurp_mc(log).find("--iso-direction"), std::string::npos) << slurp_mc(log);
  EXPECT_NE(slurp_mc(log).find("predicted with normal"), std::string::npos) << slurp_mc(log);
  EXPECT_FALSE(std::filesystem::exists(dir / "e2"));
  EXPECT_EQ(run_geartopo(evaluate + (dir / "e3").string() + " --helix-slope-sign helix-angle", log), 2);
  EXPECT_NE(slurp_mc(log).find("--helix-slope-sign"), std::string::npos) << slurp_mc(log);
  EXPECT_EQ(run_geartopo(evaluate + (dir / "e4").string() + " --iso-direction normal", log), 0) << slurp_mc(log);
  // A prediction.json written before the options were recorded: accepted, evaluated with the flags as given.
  auto old = n;
  old.erase("iso_options");
  old.erase("probe_noise_um");
  { std::ofstream(dir / "old.json") << old.dump(2); }
  ASSERT_EQ(run_geartopo("evaluate " + scene + " --traces " + traces + " --prediction " + (dir / "old.json").string() +
                             " --out " + (dir / "e5").string() + " --iso-direction transverse", log), 0)
      << slurp_mc(log);
  EXPECT_EQ(nlohmann::json::parse(slurp_mc(dir / "e5" / "iso1328.json"))["before"]["iso_direction"], "transverse");
  std::filesystem::remove_all(dir);
}
