// Compensation: known errors cancelled, the methods' differences shown with numbers, the correction table.
#include "geartopo/compensation/compensator.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/grinding/topology_plan.hpp"

#include "../grinding/grinding_fixture.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <sstream>

using namespace geartopo;
using compensation::Method;
using machine::ComponentId;
using machine::ErrorSource;
using test::kDatumZ;
using test::paper_setup;

namespace {

double largest_abs(const std::vector<grinding::FlankTopology>& topo) {
  double m = 0.0;
  for (const auto& ft : topo) {
    for (const auto& p : ft.grid) m = std::max(m, std::abs(p.deviation_um));
    for (const auto& p : ft.helix) m = std::max(m, std::abs(p.deviation_um));
  }
  return m;
}

struct Outcome {
  double before_um, after_um;
  compensation::CorrectionTable table;
};

Outcome compensate(const machine::MachineModel& model, Method method, std::vector<int> teeth = {1, 18}) {
  const grinding::MachineProcess process(model, kDatumZ);
  compensation::CompensationOptions o;
  o.method = method;
  o.step_mm = 4.0;
  auto table = compensation::compute_corrections(paper_setup(), process, {model, kDatumZ}, o);
  const compensation::CompensatedProcess corrected(process, table);
  const double before = largest_abs(test::simulate(process, grinding::Method::Exact, teeth));
  const double after = largest_abs(test::simulate(corrected, grinding::Method::Exact, teeth));
  return {before, after, std::move(table)};
}

} // namespace

// One known component is cancelled by both methods (to first order: what is left is second order, < 1 %).
// (An A-axis angle error is not among them: it tilts the wheel about the common perpendicular, which changes the
// flank only to second order — the lead comes from the C–Z coupling, not from the wheel's tilt.)
TEST(Compensation, SingleComponentsAreCancelledByBothMethods) {
  for (const auto& src : {ErrorSource::constant(ComponentId::delta_xx, 10.0, "um"),
                          ErrorSource::polynomial(ComponentId::delta_xz, {2.0, 0.02}, "um", "mm"),
                          ErrorSource::constant(ComponentId::epsilon_zx, 40.0, "urad"),
                          ErrorSource::constant(ComponentId::S_xz, 30.0, "urad")}) {
    const auto model = test::machine_with({src});
    for (Method m : {Method::Paper, Method::Flank, Method::Cycle}) {
      const Outcome o = compensate(model, m);
      EXPECT_GT(o.before_um, 1.0) << src.describe();
      EXPECT_LT(o.after_um, 0.01 * o.before_um)
          << src.describe() << (m == Method::Paper ? " paper" : m == Method::Flank ? " flank" : " cycle");
    }
  }
}

// A pure C-axis offset Δγ is corrected by C alone, by both methods.
TEST(Compensation, PureCOffsetGetsAPureCCorrection) {
  const auto model = test::machine_with({ErrorSource::constant(ComponentId::epsilon_zc, 20.0, "urad")});
  for (Method m : {Method::Paper, Method::Flank}) {
    const Outcome o = compensate(model, m);
    for (const auto& row : o.table.rows()) {
      EXPECT_NEAR(row.correction(4), -20e-6, 1e-11);
      EXPECT_LT(row.correction.head<3>().norm(), 1e-8); // mm: < 0.01 µm
      EXPECT_LT(std::abs(row.correction(3)), 1e-11);
    }
    EXPECT_LT(o.after_um, 0.01);
  }
}

// A turn of the wheel about its own axis (ε_yy: the Y slide carries the spindle) changes nothing on the flank. The
// flank method leaves it alone; the paper's pseudo-inverse tries to cancel a rotation no axis can make and spoils
// the flank doing so.
TEST(Compensation, SpinAboutTheWheelAxisIsNotFought) {
  const auto model = test::machine_with({ErrorSource::constant(ComponentId::epsilon_yy, 50.0, "urad")});
  const Outcome flank = compensate(model, Method::Flank);
  const Outcome paper = compensate(model, Method::Paper);
  EXPECT_LT(flank.before_um, 0.01);
  EXPECT_LT(flank.after_um, 0.01);
  EXPECT_LT(flank.table.max_abs().head<3>().norm(), 1e-5); // < 10 nm (second-order effects of the spin only)
  EXPECT_LT(flank.table.max_abs().tail<2>().norm(), 1e-9);  // < 1 nrad
  RecordProperty("paper_after_um", std::to_string(paper.after_um));
  EXPECT_GT(paper.after_um, 0.5); // µm created by the paper's compromise
}

// The default scene with its representative machine (errors known to the model), built once for the tests below, and
// its largest uncompensated |deviation| on a 20-point trace grid.
struct DefaultScene {
  workbench::Workbench wb{std::filesystem::path(GEARTOPO_SOURCE_DIR) / "scenes/skmc1200w-mn14-z35.yaml"};
  grinding::SimulationOptions so = [] {
    grinding::SimulationOptions o;
    o.profile_points = o.helix_points = 20;
    return o;
  }();
  double before = largest_abs(grinding::simulate_topology(wb.setup, wb.machine_process, so));

  double after(const compensation::CorrectionTable& table) const {
    const compensation::CompensatedProcess corrected(wb.machine_process, table);
    return largest_abs(grinding::simulate_topology(wb.setup, corrected, so));
  }
  compensation::StrokeCheck strokes() const { return {wb.machine, wb.scene.machine.datum_face_z_mm}; }
};

const DefaultScene& default_scene() {
  static const DefaultScene s;
  return s;
}

// The flank method leaves < 5 % of the largest uncompensated |deviation|; the paper's method, reported beside it,
// does less well.
TEST(Compensation, DefaultSceneFlankBeatsFivePercentAndPaperIsReported) {
  const DefaultScene& d = default_scene();
  double after[2];
  for (Method m : {Method::Flank, Method::Paper}) {
    compensation::CompensationOptions o;
    o.method = m;
    const auto table = compensation::compute_corrections(d.wb.setup, d.wb.machine_process, d.strokes(), o);
    EXPECT_EQ(table.rows_outside_strokes(), 0);
    after[m == Method::Flank ? 0 : 1] = d.after(table);
  }
  RecordProperty("before_um", std::to_string(d.before));
  RecordProperty("flank_after_um", std::to_string(after[0]));
  RecordProperty("paper_after_um", std::to_string(after[1]));
  EXPECT_GT(d.before, 5.0);
  EXPECT_LT(after[0], 0.05 * d.before);
  EXPECT_LT(after[1], d.before);
  EXPECT_GT(after[1], after[0]);
}

// The cycle method moves only what a profile grinder's cycle can: every row carries the same Y and A corrections
// (one per gear), and with them held X, Z, C per pose still remove nearly all of the default machine's errors.
// Y straightness of the Z slide (δ_yz, varying along the stroke) is in the default tables: the unconstrained flank
// method answers it with Y pose by pose, which the cycle cannot do.
TEST(Compensation, CycleMethodHoldsYAndAPerGearAndStillCorrects) {
  const DefaultScene& d = default_scene();
  compensation::CompensationOptions o;
  o.method = Method::Cycle;
  o.step_mm = 4.0;
  const auto table = compensation::compute_corrections(d.wb.setup, d.wb.machine_process, d.strokes(), o);
  const auto& first = table.rows().front().correction;
  for (const auto& r : table.rows()) {
    EXPECT_EQ(r.correction(1), first(1)) << "Y must be one value for the gear";
    EXPECT_EQ(r.correction(3), first(3)) << "A must be one value for the gear";
  }
  const double after = d.after(table);
  RecordProperty("cycle_after_um", std::to_string(after));
  EXPECT_GT(d.before, 5.0);
  EXPECT_LT(after, 0.05 * d.before);
}

// A tilt of the wheel about the tangential axis through its centre (ε_yz with Y = 0) is a pose error no axis can
// make: in the wheel frame it is (0, ε cos A, −ε sin A), orthogonal to every column of J_M, so pinv(J_M)·E = 0 and the
// paper's method does nothing. Its effect on the flank, though, can be reproduced by other axes: the flank method
// cancels it.
TEST(Compensation, TangentialWheelTiltDefeatsThePaperButNotTheFlankMethod) {
  const auto model = test::machine_with({ErrorSource::constant(ComponentId::epsilon_yz, 40.0, "urad")});
  const Outcome paper = compensate(model, Method::Paper);
  const Outcome flank = compensate(model, Method::Flank);
  EXPECT_GT(paper.before_um, 2.0);
  EXPECT_LT(paper.table.max_abs().norm(), 1e-9);                  // no correction at all
  EXPECT_NEAR(paper.after_um, paper.before_um, 1e-6);
  EXPECT_LT(flank.after_um, 0.05 * flank.before_um);
}

// A correction that would leave a stroke is reported, not clipped.
TEST(Compensation, CorrectionsBeyondAStrokeAreReportedNotClipped) {
  auto strokes = machine::Strokes::skmc_1200w();
  strokes.x_mm.max = paper_setup().setting().centre_distance_mm + 0.001; // 1 µm of room
  const machine::MachineModel model(strokes, {ErrorSource::constant(ComponentId::delta_xx, -10.0, "um")});
  const grinding::MachineProcess process(model, kDatumZ);
  compensation::CompensationOptions o;
  o.step_mm = 10.0;
  const auto table = compensation::compute_corrections(paper_setup(), process, {model, kDatumZ}, o);
  EXPECT_EQ(table.rows_outside_strokes(), static_cast<int>(table.rows().size()));
  for (const auto& row : table.rows()) EXPECT_NEAR(row.correction(0), 0.010, 1e-6); // the full +10 µm
}

TEST(CorrectionTable, InterpolatesLinearlyAndWritesUnits) {
  std::vector<compensation::CorrectionRow> rows(3);
  rows[0].space = rows[1].space = 2;
  rows[2].space = 1;
  rows[0].z_stroke_mm = 0.0, rows[1].z_stroke_mm = 10.0, rows[2].z_stroke_mm = 5.0;
  rows[0].correction << 0.001, 0, 0, 0, 1e-6;
  rows[1].correction << 0.003, 0, 0, 0, 3e-6;
  const compensation::CorrectionTable t(rows);
  EXPECT_NEAR(t.at(2, 2.5)(0), 0.0015, 1e-15);
  EXPECT_NEAR(t.at(2, 2.5)(4), 1.5e-6, 1e-18);
  EXPECT_NEAR(t.at(2, -5.0)(0), 0.001, 1e-15); // held beyond the ends
  EXPECT_TRUE(t.at(3, 1.0).isZero());
  std::ostringstream csv;
  t.write_csv(csv);
  std::istringstream in(csv.str());
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  EXPECT_EQ(header, "space,z_stroke_mm,time_s,X_mm,Y_mm,Z_mm,A_deg,C_deg,dX_um,dY_um,dZ_um,dA_urad,dC_urad,within_strokes");
  EXPECT_EQ(first.rfind("1,5.0000,", 0), 0u) << first; // sorted by space, then stroke position
  EXPECT_NE(csv.str().find(",1.0000,0.0000,0.0000,0.0000,1.0000,yes"), std::string::npos) << csv.str();
}

namespace {

/// A machine whose wheel is 2 µm bigger in radius everywhere (a dressing error): it changes the wheel radius.
class BiggerWheel final : public grinding::GrindingProcess {
public:
  explicit BiggerWheel(const grinding::GrindingProcess& inner) : inner_(inner) {}
  machine::Pose actual_wMg(const grinding::PathPoint& pp) const override { return inner_.actual_wMg(pp); }
  machine::Vector6d error_twist_w(const grinding::PathPoint& pp) const override { return inner_.error_twist_w(pp); }
  double wheel_radius_error_mm(double, const grinding::PathPoint&) const override { return 2e-3; }

private:
  const grinding::GrindingProcess& inner_;
};

} // namespace

// The exact search skips the wheel radius of processes that never change it (GrindingProcess::changes_wheel_radius):
// a compensated process says what its inner process says. Truth: the inner process simulated on its own — an empty
// correction table changes no command, so the compensated gear must be the same to the bit, with or without a bigger
// wheel — and the bigger wheel's gear is thinner by 2 µm·normal_per_radial at each point's contact on the wheel
// (FormWheel: a radial change moves the wheel surface along its normal by δR/√(1 + R′²)), to 1e-3 µm.
TEST(CompensatedProcess, AsksTheWheelRadiusWhenTheInnerProcessChangesIt) {
  const machine::MachineModel model(machine::Strokes::skmc_1200w(), {ErrorSource::constant(ComponentId::delta_yx, 5.0, "um")});
  const grinding::MachineProcess machine_process(model, kDatumZ);
  const BiggerWheel bigger(machine_process);
  const compensation::CorrectionTable none(std::vector<compensation::CorrectionRow>{});
  const compensation::CompensatedProcess plain(machine_process, none), with_bigger(bigger, none);
  EXPECT_FALSE(machine_process.changes_wheel_radius());
  EXPECT_FALSE(plain.changes_wheel_radius());
  EXPECT_TRUE(bigger.changes_wheel_radius());
  EXPECT_TRUE(with_bigger.changes_wheel_radius());
  const auto expect_same = [](const auto& a, const auto& b) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t f = 0; f < a.size(); ++f)
      for (size_t i = 0; i < a[f].grid.size(); ++i) EXPECT_EQ(a[f].grid[i].deviation_um, b[f].grid[i].deviation_um);
  };
  const auto reference = test::simulate(machine_process, grinding::Method::Exact, {1});
  const auto reference_bigger = test::simulate(bigger, grinding::Method::Exact, {1});
  expect_same(test::simulate(plain, grinding::Method::Exact, {1}), reference);
  expect_same(test::simulate(with_bigger, grinding::Method::Exact, {1}), reference_bigger);
  const auto& setup = paper_setup();
  const grinding::FlankDeviation dev(setup.flanks(), setup.wheel(), setup.path(), machine_process);
  for (size_t f = 0; f < reference.size(); ++f)
    for (size_t i = 0; i < reference[f].grid.size(); ++i) {
      const auto& p = reference[f].grid[i];
      const double expected_um = 2.0 * dev.linear_contact(reference[f].tooth, reference[f].flank, p.roll_length_mm, p.z_mm).normal_per_radial;
      EXPECT_NEAR(p.deviation_um - reference_bigger[f].grid[i].deviation_um, expected_um, 1e-3);
    }
}

// The Monte Carlo's dense sample (bench/bench_monte_carlo.cpp): the default scene's machine ground uncorrected and
// with its flank corrections, the scene's grid and traces plus a dense 50×100 grid on both flanks of all 35 teeth
// (743 820 deviations). Newton's bounded early stop (flank_deviation.cpp) against Newton run to rounding: every
// deviation within 1e-6 µm (the stop's bound is 1e-10 µm per depth; the search's vertex moves with the depths).
TEST(CompensatedProcess, DenseDefaultSceneEarlyNewtonStopEqualsNewtonToRounding) {
  const DefaultScene& d = default_scene();
  const auto table = compensation::compute_corrections(d.wb.setup, d.wb.machine_process, d.strokes(), {});
  const compensation::CompensatedProcess corrected(d.wb.machine_process, table);
  grinding::SimulationOptions so;
  so.rows = d.wb.scene.grid.rows;
  so.cols = d.wb.scene.grid.cols;
  so.profile_points = d.wb.scene.grid.profile_points;
  so.helix_points = d.wb.scene.grid.helix_points;
  so.dense_rows = 50;
  so.dense_cols = 100;
  const grinding::TopologyPlan plan(d.wb.setup, so);
  double worst_um = 0.0;
  long long compared = 0;
  for (const grinding::GrindingProcess* p : {static_cast<const grinding::GrindingProcess*>(&d.wb.machine_process),
                                             static_cast<const grinding::GrindingProcess*>(&corrected)}) {
    const test::NewtonToRounding to_rounding(*p);
    const auto early = plan.simulate(*p, 0), full = plan.simulate(to_rounding, 0);
    ASSERT_EQ(early.size(), full.size());
    const auto compare = [&](const auto& a, const auto& b) {
      ASSERT_EQ(a.size(), b.size());
      for (size_t i = 0; i < a.size(); ++i) worst_um = std::max(worst_um, std::abs(a[i].deviation_um - b[i].deviation_um)), ++compared;
    };
    for (size_t f = 0; f < early.size(); ++f) {
      compare(early[f].grid, full[f].grid);
      compare(early[f].profile, full[f].profile);
      compare(early[f].helix, full[f].helix);
      compare(early[f].dense, full[f].dense);
    }
  }
  std::printf("dense default scene, early Newton stop vs Newton to rounding: %lld deviations, worst %.2e µm\n", compared, worst_um);
  RecordProperty("worst_um", std::to_string(worst_um));
  EXPECT_EQ(compared, 2 * plan.points());
  EXPECT_LT(worst_um, 1e-6);
}
