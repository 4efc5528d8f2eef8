// The cycle form of the corrections (per space an index C, lead X(Z) and C(Z), set-up Y and A): values against
// formulas written here, the file read back, and on the paper's gear the physics it rests on — a Z correction folded
// into C through the twist grinds the same flank.
#include "geartopo/compensation/compensator.hpp"
#include "geartopo/compensation/cycle_corrections.hpp"
#include "geartopo/grinding/chain_process.hpp"
#include "geartopo/machine/kinematic_chain.hpp"

#include "../grinding/grinding_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

using namespace geartopo;
using machine::ComponentId;
using machine::ErrorSource;

namespace {

constexpr double kTwist = 0.002; // rad/mm

/// The gear's teeth 1 and 18 ground by `process` with the full table `full` and with its cycle form (10 mm lead grid):
/// the largest difference between the two (µm), after checking that the full table uses the stroke axis (else the fold
/// is not exercised) and that the uncorrected flanks are off by more than 5 µm (else agreement proves nothing).
double cycle_against_full_um(const grinding::GrindingProcess& process, const compensation::CorrectionTable& full) {
  const double k = test::paper_setup().geometry().twist_rad_per_mm();
  const auto cycle = compensation::make_cycle_corrections(full, k, 10.0);
  double max_ds = 0.0;
  for (const auto& r : full.rows()) max_ds = std::max(max_ds, std::abs(r.correction(cycle.stroke_slot)));
  EXPECT_GT(max_ds, 1e-3) << "the full table must use the stroke axis for this test to mean anything";
  std::vector<compensation::CorrectionRow> rows = full.rows();
  for (auto& r : rows) r.correction = cycle.at(r);
  const compensation::CorrectionTable as_cycle(std::move(rows), full.axes());
  const compensation::CompensatedProcess with_full(process, full), with_cycle(process, as_cycle);
  const auto a = test::simulate(with_full, grinding::Method::Exact, {1, 18});
  const auto b = test::simulate(with_cycle, grinding::Method::Exact, {1, 18});
  const auto before = test::simulate(process, grinding::Method::Exact, {1, 18});
  double diff = 0.0, largest_before = 0.0;
  for (size_t f = 0; f < a.size(); ++f)
    for (size_t i = 0; i < a[f].grid.size(); ++i) {
      diff = std::max(diff, std::abs(a[f].grid[i].deviation_um - b[f].grid[i].deviation_um));
      largest_before = std::max(largest_before, std::abs(before[f].grid[i].deviation_um));
    }
  EXPECT_GT(largest_before, 5.0);
  return diff;
}

// Two spaces, 100 samples each over machine Z 250 … 400 mm (not on any 10 mm grid):
//   δX = 2 µm + 1e-6 mm⁻¹ (Z − 325)²,  δY = 1 µm + 0.2 µm sin(Z/7),  δZ = ±5 µm (space 1 / 2),
//   εA = 10 µrad + 1 µrad cos(Z/5),    εC = 20 µrad (space 1) or −30 µrad (space 2) + 0.1 µrad/mm (Z − 325).
compensation::CorrectionTable analytic_table() {
  std::vector<compensation::CorrectionRow> rows;
  for (int space : {1, 2})
    for (int i = 0; i < 100; ++i) {
      compensation::CorrectionRow r;
      r.space = space;
      const double z = 250.0 + 150.0 * i / 99.0;
      r.machine_axes.z = z;
      r.z_stroke_mm = z - 300.0;
      const double dz = space == 1 ? 5e-3 : -5e-3;
      const double c0 = space == 1 ? 20e-6 : -30e-6;
      r.correction << 2e-3 + 1e-6 * (z - 325.0) * (z - 325.0), 1e-3 + 2e-4 * std::sin(z / 7.0), dz,
          10e-6 + 1e-6 * std::cos(z / 5.0), c0 + 1e-7 * (z - 325.0);
      rows.push_back(r);
    }
  return compensation::CorrectionTable(std::move(rows));
}

} // namespace

TEST(CycleCorrections, IndexLeadAndSetUpFollowTheFormulas) {
  const auto table = analytic_table();
  const auto cycle = compensation::make_cycle_corrections(table, kTwist, 10.0);
  ASSERT_EQ(cycle.spaces.size(), 2u);
  for (const auto& s : cycle.spaces) {
    ASSERT_EQ(s.z_mm.size(), 16u); // 150 mm in 15 steps of 10 mm
    const double dz = s.space == 1 ? 5e-3 : -5e-3;
    const double c0 = s.space == 1 ? 20e-6 : -30e-6;
    // Index: the mean over the stroke of εC + k·δZ; the linear part has mean 0 over 250 … 400.
    EXPECT_NEAR(s.index_dC_rad, c0 + kTwist * dz, 1e-12);
    for (size_t i = 0; i < s.z_mm.size(); ++i) {
      const double z = 250.0 + 10.0 * static_cast<double>(i);
      EXPECT_NEAR(s.z_mm[i], z, 1e-9);
      EXPECT_NEAR(s.dC_rad[i], 1e-7 * (z - 325.0), 1e-12); // linear: exact under linear interpolation
      // Quadratic sampled every 150/99 mm: linear interpolation errs by at most h²/8·f'' = 0.57 nm.
      EXPECT_NEAR(s.dX_mm[i], 2e-3 + 1e-6 * (z - 325.0) * (z - 325.0), 6e-7);
    }
  }
  double mean_y = 0.0, mean_a = 0.0;
  for (const auto& r : table.rows()) mean_y += r.correction(1) / 200.0, mean_a += r.correction(3) / 200.0;
  EXPECT_NEAR(cycle.setup_dY_mm, mean_y, 1e-15);
  EXPECT_NEAR(cycle.setup_dA_rad, mean_a, 1e-18);
  double y_left = 0.0, a_left = 0.0;
  for (const auto& r : table.rows())
    y_left = std::max(y_left, std::abs(r.correction(1) - mean_y)), a_left = std::max(a_left, std::abs(r.correction(3) - mean_a));
  EXPECT_NEAR(cycle.y_not_carried_mm, y_left, 1e-15);
  EXPECT_GT(cycle.y_not_carried_mm, 1.9e-4); // the 0.2 µm sine is what the cycle cannot apply
  EXPECT_NEAR(cycle.a_not_carried_rad, a_left, 1e-18);
}

TEST(CycleCorrections, TheFileReadsBackToItsPrintedPrecision) {
  const auto cycle = compensation::make_cycle_corrections(analytic_table(), kTwist, 10.0);
  std::ostringstream out;
  cycle.write_csv(out);
  std::istringstream in(out.str());
  std::string line;
  bool header = false;
  size_t rows = 0;
  double setup_y_um = NAN;
  while (std::getline(in, line)) {
    if (line.rfind("# setup_dY_um: ", 0) == 0) setup_y_um = std::stod(line.substr(15));
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      EXPECT_EQ(line, "space,index_dC_urad,Z_mm,lead_dX_um,lead_dC_urad");
      header = true;
      continue;
    }
    std::istringstream f(line);
    std::string v[5];
    for (auto& s : v) std::getline(f, s, ',');
    const int space = std::stoi(v[0]);
    const auto& s = cycle.spaces[static_cast<size_t>(space - 1)];
    const size_t i = rows % 16;
    EXPECT_NEAR(std::stod(v[1]), 1e6 * s.index_dC_rad, 1e-4);
    EXPECT_NEAR(std::stod(v[2]), s.z_mm[i], 1e-4);
    EXPECT_NEAR(std::stod(v[3]), 1e3 * s.dX_mm[i], 1e-4);
    EXPECT_NEAR(std::stod(v[4]), 1e6 * s.dC_rad[i], 1e-4);
    ++rows;
  }
  EXPECT_EQ(rows, 32u);
  EXPECT_NEAR(setup_y_um, 1e3 * cycle.setup_dY_mm, 1e-4);
}

TEST(CycleCorrections, RefusesAnEmptyTableAndABadStep) {
  EXPECT_THROW(compensation::make_cycle_corrections(compensation::CorrectionTable({}), kTwist, 10.0),
               std::invalid_argument);
  EXPECT_THROW(compensation::make_cycle_corrections(analytic_table(), kTwist, 0.0), std::invalid_argument);
  EXPECT_THROW(compensation::make_cycle_corrections(analytic_table(), kTwist, NAN), std::invalid_argument);
}

// A machine whose Z positions 8 µm long and whose C is 15 µrad off: the flank method corrects with Z and C. The
// cycle table has no Z; it folds δZ into C through the twist. Ground with the cycle's corrections the flanks must
// be those ground with the full table — the screw motion (Z by s, C by −k·s) does not change a helicoid — to
// within the lead grid's interpolation (a few nm here).
TEST(CycleCorrections, AZCorrectionFoldedIntoCGrindsTheSameFlank) {
  const auto model = test::machine_with({ErrorSource::constant(ComponentId::delta_zz, 8.0, "um"),
                                         ErrorSource::constant(ComponentId::epsilon_zc, 15.0, "urad"),
                                         ErrorSource::constant(ComponentId::delta_xx, 6.0, "um")});
  const grinding::MachineProcess process(model, test::kDatumZ);
  compensation::CompensationOptions o;
  o.step_mm = 4.0;
  const auto full = compensation::compute_corrections(test::paper_setup(), process, {model, test::kDatumZ}, o);
  EXPECT_LT(cycle_against_full_um(process, full), 0.01) << "µm: folding Z into C must not change the flank";
}

namespace {

const machine::KinematicChain& cafxzy() { return *machine::chain_preset("CAFXZY"); }

} // namespace

// On the CAFXZY (w → C → A → F → X → Z → Y → g, the C table 150 mm above the A pivot) the axes for a setting are
// X = x, Y = y + (z + 150)·sin α, Z = (z + 150)·cos α, A = −α, C = γ. The screw along the gear axis (setting z by 1,
// γ by −k) moves them by σ = (0, sin α, cos α, 0, −k), so folding δZ away along it gives δX, δY − δZ·tan α, 0, εA,
// εC + k·δZ/cos α: the expectation written here, at a cross angle of 20° (not the setting's fold, εC + k·δZ, δY).
TEST(CycleCorrections, OnAnotherChainZIsFoldedAlongTheScrewInTheChainsAxes) {
  const double alpha = 20.0 * std::numbers::pi / 180.0, z0 = 300.0;
  std::vector<compensation::CorrectionRow> rows;
  const machine::Vector5d dtheta = (machine::Vector5d() << 3e-3, 2e-3, 5e-3, 10e-6, 20e-6).finished();
  for (int i = 0; i < 20; ++i) {
    compensation::CorrectionRow r;
    r.z_stroke_mm = -20.0 + 2.0 * i;
    const double w = r.z_stroke_mm + z0 + 150.0;
    r.machine_axes = {400.0, 10.0 + w * std::sin(alpha), w * std::cos(alpha), -alpha, 0.3 * i};
    r.correction = dtheta;
    rows.push_back(r);
  }
  const compensation::CorrectionTable table(std::move(rows), {&cafxzy(), z0});
  const auto cycle = compensation::make_cycle_corrections(table, kTwist, 10.0);
  machine::Vector5d expected;
  expected << 3e-3, 2e-3 - 5e-3 * std::tan(alpha), 0.0, 10e-6, 20e-6 + kTwist * 5e-3 / std::cos(alpha);
  for (const auto& r : table.rows()) {
    const machine::Vector5d got = cycle.at(r);
    EXPECT_LT((got.head<3>() - expected.head<3>()).cwiseAbs().maxCoeff(), 1e-12) << "mm at Z " << r.machine_axes.z;
    EXPECT_LT((got.tail<2>() - expected.tail<2>()).cwiseAbs().maxCoeff(), 1e-14) << "rad at Z " << r.machine_axes.z;
  }
  EXPECT_EQ(cycle.chain, "CAFXZY");
  EXPECT_LT(cycle.y_not_carried_mm, 1e-12);
  // The setting's fold would have left δY and carried εC + k·δZ: 1.8 µm and 0.6 µrad off here.
  EXPECT_GT(std::abs(expected(1) - 2e-3), 1e-3);
}

// The physics on the CAFXZY: a Z slide that positions 8 µm long, a C 15 µrad off and an X 6 µm long; the flank
// method corrects in the chain's own axes (Z among them), the cycle table folds Z away along the chain's screw. Ground
// with the cycle's corrections the flanks are those ground with the full table (a helicoid is unchanged by its screw),
// to within the lead grid's interpolation.
TEST(CycleCorrections, OnAnotherChainAZCorrectionFoldedAlongItsScrewGrindsTheSameFlank) {
  const auto model = test::machine_with({ErrorSource::constant(ComponentId::delta_zz, 8.0, "um"),
                                         ErrorSource::constant(ComponentId::epsilon_zc, 15.0, "urad"),
                                         ErrorSource::constant(ComponentId::delta_xx, 6.0, "um")});
  const grinding::ChainProcess process(cafxzy(), model, test::kDatumZ);
  compensation::CompensationOptions o;
  o.step_mm = 4.0;
  const auto full =
      compensation::compute_corrections(test::paper_setup(), process, {model, test::kDatumZ, &cafxzy()}, o);
  EXPECT_LT(cycle_against_full_um(process, full), 0.01) << "µm: folding Z along the chain's screw must not change the flank";
}

namespace {

/// A user's chain with the CFXZAY's geometry and other letters (python/tests/test_chain.py, tests/app): the radial
/// slide U, the stroke Z, the swivel B, the shift Y — w → C → F → U → Z → B → Y → g. Pose order Y, Z, U, B, C: its
/// slot Z is the radial U, the stroke is in slot Y.
const machine::KinematicChain& cfuzby() {
  using machine::AxisKind;
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  constexpr double deg = std::numbers::pi / 180.0;
  return machine::make_chain({"CFUZBY",
                              {{"C", AxisKind::Rotary, z, Eigen::Vector3d::Zero(), std::nullopt}},
                              {{"U", AxisKind::Linear, x, Eigen::Vector3d::Zero(), machine::Interval{0.0, 900.0}},
                               {"Z", AxisKind::Linear, z, Eigen::Vector3d::Zero(), machine::Interval{0.0, 800.0}},
                               {"B", AxisKind::Rotary, x, Eigen::Vector3d::Zero(), machine::Interval{-45 * deg, 45 * deg}},
                               {"Y", AxisKind::Linear, y, Eigen::Vector3d::Zero(), machine::Interval{-200.0, 200.0}}}});
}

} // namespace

// On the CFUZBY the screw along the gear axis moves Z (pose slot Y) by 1 mm per mm and C by −k, nothing else: σ =
// (0, 1, 0, 0, −k) in pose order. So Z is the stroke axis (not slot Z, which is U), U the lead axis (it is the centre
// distance), Y the set-up axis, and the fold is the CFXZAY's in these letters: δY, 0, δU, εB, εC + k·δZ — the
// expectation written here. The file carries the chain's letters.
TEST(CycleCorrections, OnAChainWhoseSlotZIsNotTheStrokeTheFoldFollowsTheGeometry) {
  const double alpha = 20.0 * std::numbers::pi / 180.0, z0 = 300.0;
  const machine::Vector5d dtheta = (machine::Vector5d() << 2e-3, 5e-3, 3e-3, 10e-6, 20e-6).finished(); // δY δZ δU εB εC
  std::vector<compensation::CorrectionRow> rows;
  for (int i = 0; i < 20; ++i) {
    compensation::CorrectionRow r;
    r.z_stroke_mm = -20.0 + 2.0 * i;
    r.machine_axes = machine::AxisPose::from_vector(
        cfuzby().axes({400.0, 10.0, r.z_stroke_mm + z0, alpha, 0.3 * i}).v);
    r.correction = dtheta;
    rows.push_back(r);
  }
  // The chain's axes for that setting: Y = y, Z = z, U = x, B = α (its geometry is the CFXZAY's).
  EXPECT_NEAR(rows[3].machine_axes.x, 10.0, 1e-9);
  EXPECT_NEAR(rows[3].machine_axes.y, rows[3].z_stroke_mm + z0, 1e-9);
  EXPECT_NEAR(rows[3].machine_axes.z, 400.0, 1e-9);
  const compensation::CorrectionTable table(std::move(rows), {&cfuzby(), z0});
  const auto cycle = compensation::make_cycle_corrections(table, kTwist, 10.0);
  EXPECT_EQ(cycle.stroke_slot, 1);
  EXPECT_EQ(cycle.lead_slot, 2);
  EXPECT_EQ(cycle.setup_slot, 0);
  machine::Vector5d expected;
  expected << 2e-3, 0.0, 3e-3, 10e-6, 20e-6 + kTwist * 5e-3;
  for (const auto& r : table.rows()) {
    const machine::Vector5d got = cycle.at(r);
    EXPECT_LT((got.head<3>() - expected.head<3>()).cwiseAbs().maxCoeff(), 1e-12) << "mm at Z " << r.machine_axes.y;
    EXPECT_LT((got.tail<2>() - expected.tail<2>()).cwiseAbs().maxCoeff(), 1e-14) << "rad at Z " << r.machine_axes.y;
  }
  ASSERT_EQ(cycle.spaces.size(), 1u);
  EXPECT_NEAR(cycle.spaces[0].z_mm.front(), 280.0, 1e-9); // the grid runs along the chain's Z, 280 … 318 mm
  EXPECT_NEAR(cycle.spaces[0].z_mm.back(), 318.0, 1e-9);
  EXPECT_LT(cycle.y_not_carried_mm, 1e-12);
  std::ostringstream out;
  cycle.write_csv(out);
  const std::string text = out.str();
  EXPECT_NE(text.find("\nspace,index_dC_urad,Z_mm,lead_dU_um,lead_dC_urad\n"), std::string::npos) << text;
  EXPECT_NE(text.find("# setup_dY_um: 2.0000\n# setup_dB_urad: 10.0000\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\n1,30.0000,280.0000,3.0000,0.0000\n"), std::string::npos) << text; // εC + k·δZ = 30 µrad
}

// The physics on the CFUZBY: its Z slide positions 8 µm long, its C is 15 µrad off and its U 6 µm long; the flank
// method corrects in its own axes (Z among them), the cycle table folds Z away along the screw. Ground with the
// cycle's corrections the flanks are those ground with the full table, as on the CAFXZY.
TEST(CycleCorrections, OnAChainWhoseSlotZIsNotTheStrokeAFoldedCorrectionGrindsTheSameFlank) {
  const auto& chain = cfuzby();
  const auto id = [&](const char* name) { return *chain.component_from_name(name); };
  const auto model = test::machine_with({ErrorSource::constant(id("delta_zz"), 8.0, "um"),
                                         ErrorSource::constant(id("epsilon_zc"), 15.0, "urad"),
                                         ErrorSource::constant(id("delta_xu"), 6.0, "um")});
  const grinding::ChainProcess process(chain, model, test::kDatumZ);
  compensation::CompensationOptions o;
  o.step_mm = 4.0;
  const auto full = compensation::compute_corrections(test::paper_setup(), process, {model, test::kDatumZ, &chain}, o);
  EXPECT_EQ(compensation::make_cycle_corrections(full, 0.002, 10.0).stroke_slot, 1); // Z, pose slot Y
  EXPECT_LT(cycle_against_full_um(process, full), 0.01) << "µm: folding Z along the chain's screw must not change the flank";
}

// Where no linear axis follows the gear axis by 0.1 mm per mm at every row there is nothing to carry the stroke: rows
// of the CAFXZY at a cross angle of 5° (σ = (0, 0.087, 0.996, 0, −k)) and 85° (σ = (0, 0.996, 0.087, 0, −k)) leave
// each linear axis below 0.1 at some row. Refused with NoStrokeAxis (compensate then writes no cycle table and warns).
TEST(CycleCorrections, NoLinearAxisCarryingTheStrokeAtEveryRowIsNoStrokeAxis) {
  std::vector<compensation::CorrectionRow> rows;
  for (int i = 0; i < 20; ++i) {
    compensation::CorrectionRow r;
    r.z_stroke_mm = -20.0 + 2.0 * i;
    const double alpha = (i % 2 == 0 ? 5.0 : 85.0) * std::numbers::pi / 180.0;
    const double w = r.z_stroke_mm + 300.0 + 150.0;
    r.machine_axes = {400.0, 10.0 + w * std::sin(alpha), w * std::cos(alpha), -alpha, 0.3 * i};
    r.correction << 3e-3, 2e-3, 5e-3, 10e-6, 20e-6;
    rows.push_back(r);
  }
  const compensation::CorrectionTable table(std::move(rows), {&cafxzy(), 300.0});
  try {
    compensation::make_cycle_corrections(table, kTwist, 10.0);
    ADD_FAILURE() << "no axis carries the stroke at every row: expected NoStrokeAxis";
  } catch (const compensation::NoStrokeAxis& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("CAFXZY"), std::string::npos) << what;
    EXPECT_NE(what.find("cannot be folded"), std::string::npos) << what;
    EXPECT_NE(what.find("0.0872"), std::string::npos) << what; // cos 85° = sin 5°
  }
}
