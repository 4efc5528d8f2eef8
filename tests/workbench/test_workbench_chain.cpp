// geartopo tests — the workbench builds the grinding process from the scene's chain (issue 42): the CFXZAY keeps
// MachineProcess, any other chain grinds through a ChainProcess whose path is checked at set-up.
//
// Physics: a constant positioning error δ of the X slide moves the wheel away from the gear along the centre distance
// on both layouts (on the CAFXZY the A table tilts about x, which leaves x alone; the C table turns the gear and the
// setting alike), so both grind the same flanks.
// Units: mm, µm.
#include "geartopo/compensation/compensator.hpp"
#include "geartopo/diagnosis/effect_contribution.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/diagnosis/stroke_scatter.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/grinding/chain_process.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/twist.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/workbench/workbench.hpp"

#include "../chain_scene_fixture.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <vector>
#include <cstdio>

using namespace geartopo;
using namespace geartopo::chain_fixture;

TEST(WorkbenchChain, TheCfxzayKeepsMachineProcessAnyOtherChainGrindsThroughItsChain) {
  const workbench::Workbench seed(scene::parse_scene(kGearAndWheel, "mem"));
  EXPECT_NE(dynamic_cast<const grinding::MachineProcess*>(&seed.machine_process), nullptr);
  const workbench::Workbench other(scene::parse_scene(kGearAndWheel + "machine:\n  chain: CAFXZY\n", "mem"));
  const auto* chain = dynamic_cast<const grinding::ChainProcess*>(&other.machine_process);
  ASSERT_NE(chain, nullptr);
  EXPECT_EQ(chain->chain().name(), "CAFXZY");
  EXPECT_EQ(chain->datum_face_z_mm(), 180.0); // the face width centred in Z [−300, 700]
}

TEST(WorkbenchChain, AConstantXErrorGrindsTheSameFlanksOnEitherLayout) {
  // Two evaluators (the compiled-in CFXZAY, the CAFXZY's chain as data with its inverse kinematics) of two layouts
  // whose X slide moves the wheel along the same line: the same flanks to 1e-4 µm (the exact search converges to
  // 1e-6 µm). The flanks thicken (plus material) by at most δ: a rigid move of δ shifts no surface point further.
  const double delta_um = 10.0;
  std::vector<std::vector<double>> dev;
  for (const std::string chain : {"CFXZAY", "CAFXZY"})
    dev.push_back(grid_deviations(workbench::Workbench(scene::parse_scene(
        kGearAndWheel + "machine:\n  chain: " + chain + "\n  constants: {delta_xx_um: 10}\n", "mem"))));
  ASSERT_EQ(dev[0].size(), dev[1].size());
  ASSERT_EQ(dev[0].size(), 100u);
  for (std::size_t i = 0; i < dev[0].size(); ++i) {
    EXPECT_NEAR(dev[1][i], dev[0][i], 1e-4) << i;
    EXPECT_GT(dev[0][i], 0.0) << i;
    EXPECT_LE(dev[0][i], delta_um) << i;
  }
}

TEST(WorkbenchChain, APathOutsideTheChainsStrokesIsRefusedAtTheChainNamingThePointAndTheAxis) {
  // Y = y + (z + 150)·sin α on the CAFXZY (docs/machine-model.md §9): 330…370 mm along the tilted gear axis at α = 15°
  // puts Y at 85…96 mm, outside ±20.
  const auto e = workbench_error_of(kGearAndWheel + "machine:\n  chain: CAFXZY\n  strokes: {y_mm: [-20, 20]}\n");
  EXPECT_NE(e.find("scenes/x.yaml:12:10: machine.chain: CAFXZY chain, space "), std::string::npos) << e;
  EXPECT_NE(e.find(": Y = "), std::string::npos) << e;
  EXPECT_NE(e.find("mm is outside its stroke [-20, 20] mm"), std::string::npos) << e;
}

// machine_changes on the CAFXZY act through its own first-order twist (effects::ComponentChanges with the chain's
// J_twistw_e at its axes): a constant change of its A-table zero (E_AOA, 20 µrad) grinds what the same value in the
// map grinds through the chain's exact error HTMs, to second order — 20 µrad tilting the gear about the A axis line
// moves the flanks by µm (20 µrad × ~450 mm = 9 µm), the second-order terms by ~(2e-5)² of the gear's 600 mm, far
// below 0.01 µm; through the CFXZAY's twist (its tool-side swivel) the same change would move them otherwise.
TEST(WorkbenchChain, AMachineChangeOfTheCafxzyGrindsWhatTheSameErrorInItsMapGrinds) {
  const std::string chain = kGearAndWheel + "machine:\n  chain: CAFXZY\n";
  const workbench::Workbench changed(
      scene::parse_scene(chain + "machine_changes:\n  - {component: E_AOA, law: constant, change_urad: 20}\n", "mem"));
  const workbench::Workbench mapped(
      scene::parse_scene(kGearAndWheel + "machine:\n  chain: CAFXZY\n  constants: {E_AOA_urad: 20}\n", "mem"));
  const workbench::Workbench plain(scene::parse_scene(chain, "mem"));
  EXPECT_EQ(changed.effect_types(), std::vector<std::string>{"E_AOA constant"});
  const auto a = grid_deviations(changed), b = grid_deviations(mapped), zero = grid_deviations(plain);
  ASSERT_EQ(a.size(), b.size());
  double largest = 0.0, differ = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    largest = std::max(largest, std::abs(b[i] - zero[i]));
    differ = std::max(differ, std::abs(a[i] - b[i]));
  }
  EXPECT_GT(largest, 1.0);
  EXPECT_LT(differ, 0.01);
}

// The same on the CFXZAY: a machine change acts at the machine's axes (Z = z + z₀) and its twist is referred back to
// the datum, as the map's errors are (MachineProcess). Through the twist at the path's own z the C table and the X slide
// sat z₀ (380 mm here) too close to the wheel: a 20 µrad tilt of either, or S_xz, ground the flanks up to ~2.6 µm
// otherwise than the same constant in the map.
TEST(WorkbenchChain, AMachineChangeOfTheCfxzayGrindsWhatTheSameErrorInItsMapGrinds) {
  const workbench::Workbench plain(scene::parse_scene(kGearAndWheel, "mem"));
  ASSERT_GT(plain.scene.machine.datum_face_z_mm, 100.0);
  const auto zero = grid_deviations(plain);
  for (const std::string component : {"E_BOC", "epsilon_yx", "S_xz"}) {
    const workbench::Workbench changed(scene::parse_scene(
        kGearAndWheel + "machine_changes:\n  - {component: " + component + ", law: constant, change_urad: 20}\n", "mem"));
    const workbench::Workbench mapped(
        scene::parse_scene(kGearAndWheel + "machine:\n  constants: {" + component + "_urad: 20}\n", "mem"));
    const auto a = grid_deviations(changed), b = grid_deviations(mapped);
    ASSERT_EQ(a.size(), b.size());
    double largest = 0.0, differ = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      largest = std::max(largest, std::abs(b[i] - zero[i]));
      differ = std::max(differ, std::abs(a[i] - b[i]));
    }
    EXPECT_GT(largest, 1.0) << component;
    EXPECT_LT(differ, 0.01) << component;
  }
}

// The shipped CAFXZY scene (scenes/cafxzy-mn14-z35.yaml): its first-order pose error twist (the chain's 6×43 error
// Jacobian times the components) is the linearisation of its exact pose (the chain's error HTMs): at path points over
// the whole grinding order they differ by second-order terms, below 1 % of the twist (components of tens of µrad and
// a few µm: second order ~1e-4 of the first), as the CFXZAY's do (tests/effects, EveryEffect).
TEST(WorkbenchChain, TheShippedCafxzySceneFirstOrderTwistIsTheLinearisationOfTheExactPose) {
  const workbench::Workbench wb(std::filesystem::path(GEARTOPO_SOURCE_DIR) / "scenes/cafxzy-mn14-z35.yaml");
  ASSERT_NE(dynamic_cast<const grinding::ChainProcess*>(&wb.machine_process), nullptr);
  double worst = 0.0, size = 0.0;
  const auto& strokes = wb.setup.path().strokes();
  for (std::size_t k = 0; k < strokes.size(); k += 7)
    for (double f : {0.0, 0.5, 1.0}) {
      const auto& st = strokes[k];
      const auto pp = wb.setup.path().point(st.space, st.z_begin_mm + f * (st.z_end_mm - st.z_begin_mm));
      const machine::Vector6d exact =
          machine::pose_error_twist(wb.machine_process.actual_wMg(pp) * machine::ideal_wMg(pp.q).inverse());
      worst = std::max(worst, (wb.machine_process.error_twist_w(pp) - exact).cwiseAbs().maxCoeff());
      size = std::max(size, exact.cwiseAbs().maxCoeff());
    }
  EXPECT_GT(size, 1e-3); // mm or rad: the constants move the wheel by µm over the gear's 600 mm
  EXPECT_LT(worst, 0.01 * size);
}

// A constant A-table zero error E_AOA of the CAFXZY (the table turns to A + E_AOA wherever it is commanded) tilts
// the gear on it, rigidly about the A axis line (machine x, 150 mm below the C table's face), and a constant
// straightness error δ_y of the Z slide (delta_yz) moves the wheel head along y, which the Y slide carries too (no
// rotary axis between them: translations commute). In the chain's own axes each is undone by one axis alone:
// ΔA = −E_AOA and ΔY = −δ_yz at every row, the other three zero — written here from the joints, not taken from the
// code. (In the setting's coordinates the A error would have needed Y and Z corrections of ~45 µm as well: the
// table's tilt about its pivot moves the gear.) The table's axes are the chain's, by its inverse kinematics written
// here from the layout w → C → A → F → X → Z → Y → g (docs/machine-model.md §9): X = x, Y = y + (z + 150)·sin α,
// Z = (z + 150)·cos α, A = −α, C = γ, z the chain's setting (the gear's z plus its datum face). After the corrections
// the flanks are the error-free ones to 0.01 µm, while the errors alone leave tens of µm (100 µrad over the ~450 mm
// from the A axis to the flank).
TEST(WorkbenchChain, ConstantErrorsOfTheCafxzyAreCorrectedInItsOwnAxesAndCompensatedAway) {
  const workbench::Workbench wb(scene::parse_scene(
      kGearAndWheel + "machine:\n  chain: CAFXZY\n  constants: {E_AOA_urad: 100, delta_yz_um: 8}\n", "mem"));
  const double z0 = wb.scene.machine.datum_face_z_mm;
  compensation::CompensationOptions o;
  o.step_mm = 5.0;
  const auto table = compensation::compute_corrections(wb.setup, wb.process(), {wb.machine, z0, wb.scene.machine.chain}, o);
  ASSERT_FALSE(table.axes().is_setting());

  std::map<std::pair<int, double>, machine::AxisPose> setting; // the commands the rows stand for
  for (const auto& pp : wb.setup.path().sample(o.step_mm)) setting[{pp.space, pp.z_stroke_mm}] = pp.q;
  ASSERT_EQ(table.rows().size(), setting.size());
  for (const auto& r : table.rows()) {
    const machine::AxisPose& q = setting.at({r.space, r.z_stroke_mm});
    const double zc = q.z + z0 + 150.0; // from the A pivot along the gear axis
    EXPECT_NEAR(r.machine_axes.x, q.x, 1e-9);
    EXPECT_NEAR(r.machine_axes.y, q.y + zc * std::sin(q.a), 1e-9);
    EXPECT_NEAR(r.machine_axes.z, zc * std::cos(q.a), 1e-9);
    EXPECT_NEAR(r.machine_axes.a, -q.a, 1e-12);
    EXPECT_NEAR(std::remainder(r.machine_axes.c - q.c, 2.0 * std::numbers::pi), 0.0, 1e-12);
    EXPECT_NEAR(r.correction(0), 0.0, 1e-5) << "dX, mm";
    EXPECT_NEAR(r.correction(1), -8e-3, 1e-5) << "dY, mm";
    EXPECT_NEAR(r.correction(2), 0.0, 1e-5) << "dZ, mm";
    EXPECT_NEAR(r.correction(3), -100e-6, 1e-8) << "dA, rad";
    EXPECT_NEAR(r.correction(4), 0.0, 1e-8) << "dC, rad";
    EXPECT_TRUE(r.within_strokes);
  }

  const compensation::CompensatedProcess corrected(wb.process(), table);
  grinding::SimulationOptions so;
  so.teeth = {1, 16};
  so.rows = 5, so.cols = 5, so.profile_points = 2, so.helix_points = 2;
  const auto largest = [&](const grinding::GrindingProcess& p) {
    double m = 0.0;
    for (const auto& flank : grinding::simulate_topology(wb.setup, p, so))
      for (const auto& g : flank.grid) m = std::max(m, std::abs(g.deviation_um));
    return m;
  };
  const double before = largest(wb.process()), after = largest(corrected);
  EXPECT_GT(before, 10.0);
  EXPECT_LT(after, 0.01);
}

// The stroke check is the chain's own: the same corrections outside a Y stroke the chain's inverse kinematics needs
// (Y = y + (z + 150)·sin α reaches 220…305 mm on this gear) are flagged row by row, not against the CFXZAY's.
TEST(WorkbenchChain, CorrectionsAreCheckedAgainstTheChainsOwnStrokes) {
  const workbench::Workbench wb(
      scene::parse_scene(kGearAndWheel + "machine:\n  chain: CAFXZY\n  constants: {delta_yz_um: 8}\n", "mem"));
  compensation::CompensationOptions o;
  o.step_mm = 10.0;
  const auto table = compensation::compute_corrections(
      wb.setup, wb.process(), {wb.machine, wb.scene.machine.datum_face_z_mm, wb.scene.machine.chain}, o);
  double y_max = -1e9;
  for (const auto& r : table.rows()) y_max = std::max(y_max, r.machine_axes.y + r.correction(1));
  // A chain whose Y stroke ends just below the highest corrected Y: exactly the rows above it are outside.
  const auto& tight = wb.scene.machine.chain->with_strokes(
      {std::nullopt, machine::Interval{-500.0, y_max - 1e-3}, std::nullopt, std::nullopt, std::nullopt});
  const auto checked = compensation::compute_corrections(
      wb.setup, wb.process(), {wb.machine, wb.scene.machine.datum_face_z_mm, &tight}, o);
  int outside = 0, expected = 0;
  for (size_t i = 0; i < checked.rows().size(); ++i) {
    const auto& r = checked.rows()[i];
    expected += r.machine_axes.y + r.correction(1) > y_max - 1e-3 ? 1 : 0;
    outside += r.within_strokes ? 0 : 1;
  }
  EXPECT_GE(expected, 1);
  EXPECT_EQ(outside, expected);
  EXPECT_EQ(table.rows_outside_strokes(), 0);
}

// The design motions of a helix crowning on the CAFXZY are its own axes, checked against its own strokes: radial
// infeed moves the X slide alone (the centre distance, X = x) and a 6 µm crowning takes the wheel in towards the face
// ends by µm (the ends relieved); an X stroke starting 1 to 2 µm inside the path's centre distance keeps the path
// inside (the chain's path check passes) but not the motions, and the workbench refuses at gear.modifications naming the
// first sample outside and the axis with its stroke, as it names a path point outside.
TEST(WorkbenchChain, DesignMotionsOutsideTheChainsStrokesAreRefusedNamingThePointAndTheAxis) {
  const std::string crowned = with_line(kGearAndWheel, "  face_width_mm: 40\n",
                                        "  modifications:\n    both: {helix_crowning_um: 6}\n", Where::After);
  ASSERT_FALSE(crowned.empty());
  const std::string chain = crowned + "process:\n  lead_crowning: radial_infeed\nmachine:\n  chain: CAFXZY\n";
  const workbench::Workbench wb(scene::parse_scene(chain, "mem"));
  ASSERT_TRUE(wb.design_motion);
  ASSERT_FALSE(wb.design_motion->axes().is_setting());
  EXPECT_EQ(wb.design_motion->axes().chain->name(), "CAFXZY");
  EXPECT_EQ(wb.design_motion->rows_outside_strokes(), 0);
  double x_path = 0.0, dx_min = 0.0;
  for (const auto& r : wb.design_motion->rows()) {
    EXPECT_EQ(r.correction.tail<4>().norm(), 0.0) << "X alone";
    x_path = r.machine_axes.x;
    dx_min = std::min(dx_min, r.correction(0));
  }
  ASSERT_LT(dx_min, -3e-3) << "a 6 µm crowning needs µm of infeed";
  const double x_min = std::floor((x_path - 1e-3) * 1e3) / 1e3; // 1 to 2 µm inside the path, printed exactly
  const std::string tight = fmt::format("  strokes: {{x_mm: [{:.3f}, 900]}}\n", x_min);
  const auto e = workbench_error_of(chain + tight);
  EXPECT_NE(e.find("gear.modifications: the motions that grind the helix modifications leave the CAFXZY chain's "
                   "strokes at "),
            std::string::npos)
      << e;
  EXPECT_NE(e.find(", first at space "), std::string::npos) << e;
  EXPECT_NE(e.find(" mm: X = "), std::string::npos) << e;
  EXPECT_NE(e.find(fmt::format("mm is outside its stroke [{:g}, 900] mm", x_min)), std::string::npos) << e;
}

namespace {

/// Teeth 1 and 16, both flanks, a 5×5 grid over the evaluation ranges (the deviations left at 0).
std::vector<measurement::MeasuredPoint> chain_grid_points(const workbench::Workbench& wb) {
  const auto& g = wb.setup.geometry();
  const auto& r = wb.setup.ranges();
  std::vector<measurement::MeasuredPoint> pts;
  for (int tooth : {1, 16})
    for (Flank flank : {Flank::Left, Flank::Right})
      for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) {
          measurement::MeasuredPoint p;
          p.tooth = tooth, p.flank = flank;
          p.roll_length_mm = r.xi_eval_start_mm + (r.xi_eval_end_mm - r.xi_eval_start_mm) * i / 4.0;
          p.diameter_mm = g.diameter_at_roll_length(p.roll_length_mm);
          p.z_mm = r.z_eval_start_mm + (r.z_eval_end_mm - r.z_eval_start_mm) * j / 4.0;
          pts.push_back(p);
        }
  return pts;
}

} // namespace

// The diagnosis' stroke scatter on the CAFXZY offsets its own axes: a repeatability of the A table alone (R↑ 4 mdeg,
// s = 1 mdeg = 17.45 µrad) gives G a column equal to what the same constant offset of A grinds through the exact chain
// — written here as its zero error E_AOA = s in the map (the table turns to A + E_AOA wherever commanded, as a
// command A + s turns it), ground by the exact search through the chain's error HTMs — and likewise a repeatability
// of Y alone (R↑ 4 µm, s = 1 µm) and the Z slide's straightness δ_yz = s along y (the Y slide rides on it with no
// rotary axis between: translations commute). They differ by second-order terms (s² × lever arms: ~1e-4 µm) and the
// linear contact's first order against the exact search's: 0.01 µm stated. The setting's α offset by s (today's
// behaviour on the CFXZAY, where A is the setting's α) would have tilted the wheel instead of the table: a column
// that differs by more than 0.5 µm.
TEST(WorkbenchChain, StrokeScatterOfTheCafxzyOffsetsItsOwnAxes) {
  const std::string chain = kGearAndWheel + "machine:\n  chain: CAFXZY\n";
  for (const auto& [key, component, slot] : {std::tuple{"a_mdeg", "E_AOA_urad: 17.453292519943", 3},
                                             std::tuple{"y_um", "delta_yz_um: 1", 1}}) {
    std::string repeatability; // R↑ = 4 (µm or mdeg) on one axis, 0 on the others
    for (const std::string k : {"x_um", "y_um", "z_um", "a_mdeg", "c_mdeg"})
      repeatability += (repeatability.empty() ? "" : ", ") + k + (k == key ? ": 4" : ": 0");
    const workbench::Workbench wb(scene::parse_scene(chain + "  repeatability: {" + repeatability + "}\n", "mem"));
    const auto& sd = wb.scene.machine.uncertainty.repeatability;
    ASSERT_EQ((sd.array() > 0.0).count(), 1) << key;
    ASSERT_GT(sd(slot), 0.0) << key;
    const auto pts = chain_grid_points(wb);
    const compensation::ChainAxes axes{wb.scene.machine.chain, wb.scene.machine.datum_face_z_mm};
    const Eigen::MatrixXd G = diagnosis::stroke_sensitivity(wb.setup, wb.process(), pts, sd, axes); // n × 5
    const Eigen::MatrixXd G_setting = diagnosis::stroke_sensitivity(wb.setup, wb.process(), pts, sd);
    const workbench::Workbench offset(
        scene::parse_scene(chain + "  constants: {" + std::string(component) + "}\n", "mem"));
    const auto base = diagnosis::predict(wb.setup, wb.process(), pts, grinding::Method::Exact);
    const auto moved = diagnosis::predict(offset.setup, offset.process(), pts, grinding::Method::Exact);
    double differ = 0.0, largest = 0.0, setting_differ = 0.0;
    for (Eigen::Index i = 0; i < G.rows(); ++i) {
      const double exact = moved[static_cast<size_t>(i)] - base[static_cast<size_t>(i)];
      for (int a = 0; a < 5; ++a) {
        if (a != slot) {
          ASSERT_EQ(G(i, a), 0.0);
        }
      }
      differ = std::max(differ, std::abs(G(i, slot) - exact));
      largest = std::max(largest, std::abs(exact));
      setting_differ = std::max(setting_differ, std::abs(G_setting(i, slot) - exact));
    }
    std::printf("%s 4: largest |offset ground| %.4f um, G's column differs by %.5f um (the setting's by %.3f um)\n", key,
                largest, differ, setting_differ);
    EXPECT_GT(largest, 0.5) << key;
    EXPECT_LT(differ, 0.01) << key;
    if (slot == 3) {
      EXPECT_GT(setting_differ, 0.5) << key;
    }
  }
}

namespace {

/// `text` with an effects block of one thermal drift (µm, s).
std::string with_thermal_drift(const std::string& text, double x_um, double z_um, double tau_s) {
  return text + fmt::format("effects:\n  - type: thermal_drift\n    x_growth_um: {}\n    z_growth_um: {}\n"
                            "    time_constant_s: {}\n",
                            x_um, z_um, tau_s);
}

/// Largest |a − b| and largest |b − base| over the grid deviations (µm).
std::pair<double, double> differ_and_size(const std::vector<double>& a, const std::vector<double>& b,
                                          const std::vector<double>& base) {
  double differ = 0.0, size = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    differ = std::max(differ, std::abs(a[i] - b[i])), size = std::max(size, std::abs(b[i] - base[i]));
  return {differ, size};
}

} // namespace

// The thermal drift's growth belongs to the slides whose ball screws grow: X growth to the chain's slide along x (the
// centre distance), Z growth to its slide along z (effects::chain_offsets). On the CXFZAY X is the radial table on the
// workpiece side: a drift of 20 µm (τ = 60 s) grinds what the same offset of X, δX(t) = 20 µm·(1 − e^(−t/τ)) sampled
// every 0.5 mm of every stroke into a correction table, grinds through the exact chain (CompensatedProcess: the
// chain's forward kinematics at θ + δθ) — to 1e-3 µm (the table's linear interpolation of e^(−t/τ) over 25 ms: 1e-7 µm;
// the exact search: 1e-6 µm).
TEST(WorkbenchChain, ThermalXGrowthOfTheCxfzayGrindsTheSameOffsetOfItsRadialTable) {
  const std::string chain = kGearAndWheel + "machine:\n  chain: CXFZAY\n";
  const workbench::Workbench plain(scene::parse_scene(chain, "mem"));
  const workbench::Workbench drifting(scene::parse_scene(with_thermal_drift(chain, 20.0, 0.0, 60.0), "mem"));
  std::vector<compensation::CorrectionRow> rows;
  for (const auto& pp : plain.setup.path().sample(0.5)) {
    compensation::CorrectionRow r;
    r.space = pp.space, r.z_stroke_mm = pp.z_stroke_mm, r.time_s = pp.time_s;
    r.correction(0) = 20e-3 * (1.0 - std::exp(-pp.time_s / 60.0)); // X, mm
    rows.push_back(r);
  }
  const compensation::CorrectionTable offsets(
      std::move(rows), {plain.scene.machine.chain, plain.scene.machine.datum_face_z_mm});
  ASSERT_FALSE(offsets.axes().is_setting());
  ASSERT_EQ(offsets.axes().axis_name(0), "X");
  const compensation::CompensatedProcess offset(plain.process(), offsets, compensation::CorrectedPose::Exact);
  const auto a = grid_deviations(drifting), b = grid_deviations(plain);
  std::vector<double> expected;
  {
    grinding::SimulationOptions so;
    so.teeth = {1, 16};
    so.rows = 5, so.cols = 5, so.profile_points = 2, so.helix_points = 2;
    for (const auto& flank : grinding::simulate_topology(plain.setup, offset, so))
      for (const auto& p : flank.grid) expected.push_back(p.deviation_um);
  }
  ASSERT_EQ(a.size(), expected.size());
  const auto [differ, size] = differ_and_size(a, expected, b);
  std::printf("CXFZAY thermal X growth: up to %.3f um, differs from the X offset by %.2e um\n", size, differ);
  EXPECT_GT(size, 1.0);
  EXPECT_LT(differ, 1e-3);
}

// On the CAFXZY the Z slide carries the wheel head along the bed's z while the A table tilts the gear by α: at fixed
// A and Y the closed form Z = (z + 150)·cos α, Y = y + (z + 150)·sin α gives a Z offset δZ as the setting's
// δz = δZ / cos α along the gear axis and δy = −δZ·tan α along the wheel spindle (not δz = δZ, as the setting's z
// would have it). A Z growth of 20 µm (τ = 60 s) on the CAFXZY grinds what those setting offsets grind on the error-free
// CFXZAY, to 1e-3 µm, and its first-order model is the diagnosis' a_q (EffectContribution: the chain's
// J_twistw_theta) to 1e-9 µm. The bed's z lies in the wheel's mid-plane, tilted with the gear by the cross angle
// along the lead, so the growth grinds a fraction of a µm, where the setting's δz along the gear axis grinds µm.
TEST(WorkbenchChain, ThermalZGrowthOfTheCafxzyActsAlongItsZSlide) {
  const std::string cafxzy = kGearAndWheel + "machine:\n  chain: CAFXZY\n";
  const workbench::Workbench plain(scene::parse_scene(cafxzy, "mem"));
  const workbench::Workbench drifting(scene::parse_scene(with_thermal_drift(cafxzy, 0.0, 20.0, 60.0), "mem"));
  const workbench::Workbench seed(scene::parse_scene(kGearAndWheel, "mem"));
  std::vector<compensation::CorrectionRow> rows, along_z;
  for (const auto& pp : seed.setup.path().sample(0.5)) {
    compensation::CorrectionRow r;
    r.space = pp.space, r.z_stroke_mm = pp.z_stroke_mm, r.time_s = pp.time_s;
    const double dZ = 20e-3 * (1.0 - std::exp(-pp.time_s / 60.0)); // mm
    along_z.push_back(r);
    along_z.back().correction(2) = dZ; // the setting's z: what the drift did before it acted on the chain's Z
    r.correction(1) = -dZ * std::tan(pp.q.a);
    r.correction(2) = dZ / std::cos(pp.q.a);
    rows.push_back(r);
  }
  const compensation::CorrectionTable closed_form(std::move(rows)), setting_z(std::move(along_z));
  const compensation::CompensatedProcess expected_process(seed.process(), closed_form, compensation::CorrectedPose::Exact);
  const compensation::CompensatedProcess setting_process(seed.process(), setting_z, compensation::CorrectedPose::Exact);
  grinding::SimulationOptions so;
  so.teeth = {1, 16};
  so.rows = 5, so.cols = 5, so.profile_points = 2, so.helix_points = 2;
  const auto ground = [&](const grinding::GrindingProcess& p) {
    std::vector<double> out;
    for (const auto& flank : grinding::simulate_topology(seed.setup, p, so))
      for (const auto& g : flank.grid) out.push_back(g.deviation_um);
    return out;
  };
  const auto a = grid_deviations(drifting), base = grid_deviations(plain);
  const auto expected = ground(expected_process), old = ground(setting_process);
  ASSERT_EQ(a.size(), expected.size());
  const auto [differ, size] = differ_and_size(a, expected, base);
  const auto [differ_old, size_old] = differ_and_size(a, old, base);
  std::printf("CAFXZY thermal Z growth: up to %.3f um, differs from the closed form by %.2e um, from the setting's z "
              "offset by %.3f um\n",
              size, differ, differ_old);
  EXPECT_GT(size, 0.1);
  EXPECT_LT(differ, 1e-3);
  EXPECT_GT(size_old, 1.0);
  EXPECT_GT(differ_old, 1.0);

  // The diagnosis' first-order model of the same effect on the chain: EffectContribution's a_q·δθ is the linear
  // method through EffectsProcess over the ideal machine on the chain.
  const auto pts = chain_grid_points(drifting);
  const diagnosis::EffectContribution at(drifting.setup, pts, 1, drifting.scene.machine.chain,
                                         drifting.scene.machine.datum_face_z_mm);
  const grinding::IdealProcess ideal;
  const effects::EffectsProcess linear(ideal, drifting.effects, drifting.scene.machine.chain,
                                       drifting.scene.machine.datum_face_z_mm);
  const auto by_process = diagnosis::predict(drifting.setup, linear, pts, grinding::Method::Linear, 1);
  const Eigen::VectorXd by_contribution = at.evaluate_um(drifting.effects, 1);
  double worst = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    worst = std::max(worst, std::abs(by_contribution(static_cast<Eigen::Index>(i)) - by_process[i]));
    largest = std::max(largest, std::abs(by_process[i] - at.offset_um()));
  }
  EXPECT_GT(largest, 0.1);
  EXPECT_LT(worst, 1e-9);
}

// A chain is a description: the CFXZAY written with its spindle turning about −z (C = −γ) and its X slide along −x
// (X = −x, stroke [−900, 0]) is the same machine, and a physical effect must grind the same flanks on it. The servo
// lag C(t) = C_cmd(t − T) of the flipped spindle is −T·dC/dt = +T·dγ/dt in C, the same lag of the gear; a thermal
// growth of the slide along x moves the wheel along +x (effects::chain_offsets: the offsets are motions of the
// setting's coordinates). Expected: the compiled-in CFXZAY (MachineProcess, no chain) with the same effects, to 1e-4 µm
// (the exact search converges to 1e-6 µm), where a lag taken in C unturned would have ground the spaces' pitch
// errors with the opposite sign.
TEST(WorkbenchChain, EffectsGrindTheSameFlanksWhenTheChainCountsItsAxesTheOtherWay) {
  const std::string effects = "effects:\n  - type: servo_lag\n    c_lag_ms: 2\n"
                              "  - type: thermal_drift\n    x_growth_um: 20\n    time_constant_s: 60\n";
  const std::string flipped = kGearAndWheel + R"(machine:
  chain:
    name: CFXZAY counted the other way
    workpiece:
      - {name: C, kind: rotary, direction: [0, 0, -1]}
    tool:
      - {name: X, kind: linear, direction: [-1, 0, 0], stroke_mm: [-900, 0]}
      - {name: Z, kind: linear, direction: [0, 0, 1], stroke_mm: [0, 800]}
      - {name: A, kind: rotary, direction: [1, 0, 0], stroke_deg: [-45, 45]}
      - {name: Y, kind: linear, direction: [0, 1, 0], stroke_mm: [-200, 200]}
)";
  const workbench::Workbench user(scene::parse_scene(flipped + effects, "mem"));
  ASSERT_NE(dynamic_cast<const grinding::ChainProcess*>(&user.machine_process), nullptr);
  EXPECT_DOUBLE_EQ(user.scene.machine.chain->axes(machine::AxisPose{150.0, 0.0, 10.0, 0.2, 0.3}).v(4), -0.3); // C = −γ
  const auto a = grid_deviations(user);
  const auto expected = grid_deviations(workbench::Workbench(scene::parse_scene(kGearAndWheel + effects, "mem")));
  const auto plain = grid_deviations(workbench::Workbench(scene::parse_scene(kGearAndWheel, "mem")));
  ASSERT_EQ(a.size(), expected.size());
  const auto [differ, size] = differ_and_size(a, expected, plain);
  std::printf("flipped CFXZAY: servo lag + X growth up to %.3f um, differs from the CFXZAY by %.2e um\n", size, differ);
  EXPECT_GT(size, 1.0);
  EXPECT_LT(differ, 1e-4);
}
