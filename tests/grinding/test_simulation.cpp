// The line-contact grinding simulation against answers known from geometry (issue: the simulator).
#include "grinding_fixture.hpp"

#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/transforms.hpp"


using namespace geartopo;
using grinding::Method;
using machine::ComponentId;
using machine::ErrorSource;
using test::kDatumZ;
using test::ModifiedProcess;
using test::paper_setup;

namespace {

template <class F>
void for_each_point(const std::vector<grinding::FlankTopology>& topo, F&& f) {
  for (const auto& ft : topo) {
    for (const auto& p : ft.grid) f(ft, p.deviation_um);
    for (const auto& p : ft.profile) f(ft, p.deviation_um);
    for (const auto& p : ft.helix) f(ft, p.deviation_um);
  }
}

} // namespace

TEST(Simulation, NoErrorsNoDeviation) {
  const auto model = test::machine_with({});
  const grinding::MachineProcess process(model, kDatumZ);
  for (Method m : {Method::Exact, Method::Linear}) {
    const auto topo = test::simulate(process, m, {}); // all teeth
    ASSERT_EQ(topo.size(), 70u);
    for_each_point(topo, [](const auto&, double d) { EXPECT_LT(std::abs(d), 0.01); });
  }
}

// A C-axis positioning error Δγ turns the workpiece by Δγ more than commanded, i.e. the wheel by −Δγ about the gear
// axis: every right flank reads −r_b cos β_b Δγ, every left flank +r_b cos β_b Δγ, uniformly.
TEST(Simulation, ConstantCOffsetGivesUniformOppositeDeviations) {
  const double dgamma = 20e-6; // 20 µrad
  const auto model = test::machine_with({ErrorSource::constant(ComponentId::epsilon_zc, 20.0, "urad")});
  const grinding::MachineProcess process(model, kDatumZ);
  const auto& g = paper_setup().geometry();
  const double expected = 0.5 * g.base_diameter_mm() * std::cos(g.base_helix_angle()) * dgamma * 1e3; // 4.60 µm
  EXPECT_NEAR(expected, 4.604, 1e-3);
  for (Method m : {Method::Exact, Method::Linear}) {
    for_each_point(test::simulate(process, m), [&](const grinding::FlankTopology& ft, double d) {
      EXPECT_NEAR(d, -geartopo::side_sign(ft.flank) * expected, 0.01);
    });
  }
}

// A Z positioning error Δz moves the wheel along the gear axis: right flanks of a right-hand gear read −Δz sin β_b,
// left flanks +Δz sin β_b.
TEST(Simulation, ConstantZOffsetGivesUniformOppositeDeviations) {
  const auto model = test::machine_with({ErrorSource::constant(ComponentId::delta_zz, 10.0, "um")});
  const grinding::MachineProcess process(model, kDatumZ);
  const double expected = 10.0 * std::sin(paper_setup().geometry().base_helix_angle()); // 4.70 µm
  for (Method m : {Method::Exact, Method::Linear})
    for_each_point(test::simulate(process, m), [&](const grinding::FlankTopology& ft, double d) {
      EXPECT_NEAR(d, -geartopo::side_sign(ft.flank) * expected, 0.01);
    });
}

// Moving the wheel along the gear's screw (a Z shift with the matching C turn) or spinning it about its own axis
// leaves the ground flank unchanged.
TEST(Simulation, ScrewMotionAndWheelSpinLeaveTheFlankUnchanged) {
  const double k = paper_setup().geometry().twist_rad_per_mm();
  const ModifiedProcess screw([k](const grinding::PathPoint& pp) {
    machine::AxisPose q = pp.q;
    q.z += 0.7;
    q.c -= k * 0.7; // C = −θ: the space turns by +k·dz, so C by −k·dz
    return machine::ideal_wMg(q);
  });
  const ModifiedProcess spin([](const grinding::PathPoint& pp) {
    return machine::ideal_wMg(pp.q) * machine::Ry(0.3 + 1e-3 * pp.z_stroke_mm); // about the wheel's own axis
  });
  for (const auto* p : {static_cast<const grinding::GrindingProcess*>(&screw), static_cast<const grinding::GrindingProcess*>(&spin)})
    for_each_point(test::simulate(*p, Method::Exact), [](const auto&, double d) { EXPECT_LT(std::abs(d), 0.01); });
}

// Exact and first-order simulations agree within 1 % of the deviation range + 0.05 µm for errors up to 50 µm and
// 100 µrad (every one of the 43 components, varying along its axis).
TEST(Simulation, ExactAndLinearAgreeForRealisticErrors) {
  const auto model = test::random_machine(1.0, 11);
  const grinding::MachineProcess process(model, kDatumZ);
  const auto exact = test::simulate(process, Method::Exact), linear = test::simulate(process, Method::Linear);
  double lo = 1e9, hi = -1e9;
  for_each_point(exact, [&](const auto&, double d) { lo = std::min(lo, d), hi = std::max(hi, d); });
  EXPECT_GT(hi - lo, 5.0); // the errors do show
  for (size_t f = 0; f < exact.size(); ++f)
    for (size_t i = 0; i < exact[f].grid.size(); ++i)
      EXPECT_NEAR(exact[f].grid[i].deviation_um, linear[f].grid[i].deviation_um, 0.01 * (hi - lo) + 0.05);
}

// An error that depends on C differs from tooth to tooth; one that depends on Z repeats on every tooth and varies
// along the helix.
TEST(Simulation, CErrorsShowBetweenTeethZErrorsAlongTheHelix) {
  // Indexing error of the C axis, once per turn: ε_zc(γ) = 20 µrad · sin γ. Each space is ground at its own γ, so each
  // flank moves by ∓r_b cos β_b ε_zc(γ): up to ±4.6 µm, different from tooth to tooth (a cumulative pitch error).
  std::vector<double> c_rad, ez;
  for (int i = 0; i <= 36; ++i) c_rad.push_back(i * 10.0 * std::numbers::pi / 180), ez.push_back(i == 36 ? 0.0 : 20e-6 * std::sin(c_rad.back()));
  machine::TableOrigin origin;
  origin.file = "synthetic";
  const auto c_model = test::machine_with(
      {ErrorSource::table(ComponentId::epsilon_zc, geartopo::CubicSpline(c_rad, ez, geartopo::CubicSpline::Ends::Periodic), origin)});
  const grinding::MachineProcess c_process(c_model, kDatumZ);
  const auto c_topo = test::simulate(c_process, Method::Exact, {1, 9, 18, 27});
  auto mean = [](const grinding::FlankTopology& ft) {
    double s = 0;
    for (const auto& p : ft.grid) s += p.deviation_um;
    return s / ft.grid.size();
  };
  double lo = 1e9, hi = -1e9;
  for (const auto& ft : c_topo)
    if (ft.flank == geartopo::Flank::Right) lo = std::min(lo, mean(ft)), hi = std::max(hi, mean(ft));
  EXPECT_GT(hi - lo, 7.0); // µm between teeth a quarter turn apart (ideal: 2 × 4.6 × |sin|)

  // Z straightness-like error: δ_xz grows linearly along Z, 20 µm over 200 mm.
  const auto z_model = test::machine_with({ErrorSource::polynomial(ComponentId::delta_xz, {0.0, 0.1}, "um", "mm")});
  const grinding::MachineProcess z_process(z_model, kDatumZ);
  const auto z_topo = test::simulate(z_process, Method::Exact, {1, 9, 18, 27});
  for (size_t f = 2; f < z_topo.size(); ++f)
    for (size_t i = 0; i < z_topo[f].grid.size(); ++i)
      EXPECT_NEAR(z_topo[f].grid[i].deviation_um, z_topo[f % 2].grid[i].deviation_um, 1e-6);
  const auto& g = z_topo[1].grid; // tooth 1 right flank: first and last column of the middle row
  EXPECT_GT(std::abs(g[3 * 9 + 8].deviation_um - g[3 * 9].deviation_um), 3.0);
}

TEST(Simulation, HugeGridsAreRefusedBeforeAllocating) {
  const grinding::IdealProcess ideal;
  grinding::SimulationOptions o;
  o.dense_rows = 31623, o.dense_cols = 31623; // 10⁹ points per flank
  try {
    grinding::simulate_topology(paper_setup(), ideal, o);
    FAIL() << "accepted 10^9 points per flank";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("more than a simulation may hold"), std::string::npos) << e.what();
  }
}
