// geartopo tests — the CAFXZY (swivel on the workpiece side) and CXFZAY (radial axis on the workpiece side) grinders
// grinding the seed paper's gear: a constant error of each axis → flank deviations, against an independent computation
// written here (each layout's inverse kinematics in closed form and its homogeneous transforms, 4×4 by hand), and
// against the physics of a spindle positioning error.
// Units: mm, rad; deviations in µm.
#include "grinding_fixture.hpp"

#include "geartopo/grinding/chain_process.hpp"
#include "geartopo/machine/kinematic_chain.hpp"

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <optional>
#include <random>

namespace geartopo {
namespace {

using machine::Axis;
using machine::ComponentId;
using machine::ErrorVector;
using Matrix4 = Eigen::Matrix4d;

const machine::KinematicChain& cafxzy() { return *machine::chain_preset("CAFXZY"); }
const machine::KinematicChain& cxfzay() { return *machine::chain_preset("CXFZAY"); }

Matrix4 T4(double x, double y, double z) {
  Matrix4 m = Matrix4::Identity();
  m.col(3).head<3>() << x, y, z;
  return m;
}
Matrix4 R4(const Eigen::Vector3d& axis, double angle) {
  Matrix4 m = Matrix4::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  return m;
}

/// The C axis line's location errors (ISO 230-7: E_XOC, E_YOC offsets, E_AOC, E_BOC tilts) as a transform.
Matrix4 c_axis_line(const ErrorVector& e) {
  const auto E = [&](ComponentId id) { return e(machine::index(id)); };
  return T4(E(ComponentId::E_XOC), E(ComponentId::E_YOC), 0.0) * R4(Eigen::Vector3d::UnitX(), E(ComponentId::E_AOC)) *
         R4(Eigen::Vector3d::UnitY(), E(ComponentId::E_BOC));
}

/// The A axis line's location errors (E_YOA, E_ZOA offsets, E_BOA, E_COA tilts) as a transform.
Matrix4 a_axis_line(const ErrorVector& e) {
  const auto E = [&](ComponentId id) { return e(machine::index(id)); };
  return T4(0.0, E(ComponentId::E_YOA), E(ComponentId::E_ZOA)) * R4(Eigen::Vector3d::UnitY(), E(ComponentId::E_BOA)) *
         R4(Eigen::Vector3d::UnitZ(), E(ComponentId::E_COA));
}

/// T(δ)·Rx(εx)·Ry(εy)·Rz(εz) (Eq. 9's order).
Matrix4 E4(const ErrorVector& e, ComponentId first) {
  const int i = machine::index(first);
  return T4(e(i), e(i + 1), e(i + 2)) * R4(Eigen::Vector3d::UnitX(), e(i + 3)) * R4(Eigen::Vector3d::UnitY(), e(i + 4)) *
         R4(Eigen::Vector3d::UnitZ(), e(i + 5));
}

/// The CAFXZY's axes for the setting q in closed form. Ideal chain: wMg = Rz(−C)·Tz(−150)·Rx(−A)·T(X, Y, Z) (the C
/// table's face 150 mm above the A pivot); Eq. 11: wMg = Rz(−γ)·T(x, 0, z)·Rx(α)·T(0, y, 0). So C = γ, A = −α and
/// (X, Y, Z) = Rx(−α)·(x, 0, z + 150) + (0, y, 0) = (x, y + (z + 150)·sin α, (z + 150)·cos α).
machine::Vector5d cafxzy_axes(const machine::AxisPose& q) {
  const double w = q.z + 150.0;
  return (machine::Vector5d() << q.x, q.y + w * std::sin(q.a), w * std::cos(q.a), -q.a, q.c).finished();
}

/// The CAFXZY with errors, w → C → A → F → X → Z → Y → g, the workpiece side inverted (docs/machine-model.md).
Matrix4 cafxzy_wMg(const ErrorVector& e, const machine::Vector5d& t) {
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ez = Eigen::Vector3d::UnitZ();
  const auto E = [&](ComponentId id) { return e(machine::index(id)); };
  const Matrix4 S_C = c_axis_line(e), S_A = a_axis_line(e);
  const double X = t(0), Y = t(1), Z = t(2), A = t(3), C = t(4);
  const Matrix4 AMC = T4(0.0, 0.0, 150.0) * S_C * R4(ez, C + E(ComponentId::E_COC)) * E4(e, ComponentId::delta_xc);
  const Matrix4 FMA = S_A * R4(ex, A + E(ComponentId::E_AOA)) * E4(e, ComponentId::delta_xa) * S_A.inverse();
  const Matrix4 FMX = T4(X, 0.0, 0.0) * E4(e, ComponentId::delta_xx);
  const Matrix4 XMZ = T4(-Z * E(ComponentId::S_xz), 0.0, Z) * E4(e, ComponentId::delta_xz);
  const Matrix4 ZMY = T4(-Y * E(ComponentId::S_xy), Y, -Y * E(ComponentId::S_zy)) * E4(e, ComponentId::delta_xy);
  return AMC.inverse() * FMA.inverse() * FMX * XMZ * ZMY;
}

/// The CXFZAY's axes for the setting q in closed form. Ideal chain (the C table's face 250 mm above the X slide, X
/// moving the table along −x, the A axis line 120 mm above the wheel centre): wMg = Rz(−C)·Tz(−250)·T(X, 0, Z)·Rx(A)·
/// T(0, Y, −120); Eq. 11: wMg = Rz(−γ)·T(x, 0, z)·Rx(α)·T(0, y, 0). So C = γ, A = α, X = x and
/// Rx(α)·(0, Y − y, −120) = (0, 0, z + 250 − Z): Y = y − 120·tan α, Z = z + 250 + 120 / cos α.
machine::Vector5d cxfzay_axes(const machine::AxisPose& q) {
  return (machine::Vector5d() << q.x, q.y - 120.0 * std::tan(q.a), q.z + 250.0 + 120.0 / std::cos(q.a), q.a, q.c)
      .finished();
}

/// The CXFZAY with errors, w → C → X → F → Z → A → Y → g, the workpiece side inverted (docs/machine-model.md §9). X
/// runs along −x, so the axes after it lean from −x: Z by +Z·S_xz along x, Y by +Y·S_xy.
Matrix4 cxfzay_wMg(const ErrorVector& e, const machine::Vector5d& t) {
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ez = Eigen::Vector3d::UnitZ();
  const auto E = [&](ComponentId id) { return e(machine::index(id)); };
  const Matrix4 S_C = c_axis_line(e), S_A = a_axis_line(e);
  const double X = t(0), Y = t(1), Z = t(2), A = t(3), C = t(4);
  const Matrix4 XMC = T4(0.0, 0.0, 250.0) * S_C * R4(ez, C + E(ComponentId::E_COC)) * E4(e, ComponentId::delta_xc);
  const Matrix4 FMX = T4(-X, 0.0, 0.0) * E4(e, ComponentId::delta_xx);
  const Matrix4 FMZ = T4(Z * E(ComponentId::S_xz), 0.0, Z) * E4(e, ComponentId::delta_xz);
  const Matrix4 ZMA = S_A * R4(ex, A + E(ComponentId::E_AOA)) * E4(e, ComponentId::delta_xa) * S_A.inverse();
  const Matrix4 AMY = T4(0.0, 0.0, -120.0) * T4(Y * E(ComponentId::S_xy), Y, -Y * E(ComponentId::S_zy)) *
                      E4(e, ComponentId::delta_xy);
  return XMC.inverse() * FMX.inverse() * FMZ * ZMA * AMY;
}

/// A hand-written chain: its wheel pose for the errors e at the setting q (q.z from the workpiece frame's origin).
using HandChain = Matrix4 (*)(const ErrorVector& e, const machine::AxisPose& q);
Matrix4 cafxzy_hand(const ErrorVector& e, const machine::AxisPose& q) { return cafxzy_wMg(e, cafxzy_axes(q)); }
Matrix4 cxfzay_hand(const ErrorVector& e, const machine::AxisPose& q) { return cxfzay_wMg(e, cxfzay_axes(q)); }

/// The same wheel pose as a process: the gear's datum face at chain z = kDatumZ, poses back through Tz(−kDatumZ).
test::ModifiedProcess by_hand(const ErrorVector& e, HandChain chain = cafxzy_hand) {
  return test::ModifiedProcess([e, chain](const grinding::PathPoint& pp) {
    machine::AxisPose q = pp.q;
    q.z += test::kDatumZ;
    machine::Pose wMg;
    wMg.matrix() = T4(0.0, 0.0, -test::kDatumZ) * chain(e, q);
    return wMg;
  });
}

/// Constant sources for the components of e that are not zero (µm, µrad).
machine::MachineModel machine_of(const ErrorVector& e) {
  std::vector<machine::ErrorSource> sources;
  for (int k = 0; k < machine::kComponentCount; ++k) {
    if (e(k) == 0.0) continue;
    const bool angle = machine::info(machine::component_at(k)).quantity == machine::Quantity::Angle;
    sources.push_back(machine::ErrorSource::constant(machine::component_at(k), e(k) * (angle ? 1e6 : 1e3), angle ? "urad" : "um"));
  }
  return test::machine_with(std::move(sources));
}

double largest_difference(const std::vector<grinding::FlankTopology>& a, const std::vector<grinding::FlankTopology>& b,
                          double& largest_value) {
  double d = 0.0;
  largest_value = 0.0;
  EXPECT_EQ(a.size(), b.size());
  for (std::size_t f = 0; f < std::min(a.size(), b.size()); ++f) {
    EXPECT_EQ(a[f].grid.size(), b[f].grid.size());
    for (std::size_t i = 0; i < std::min(a[f].grid.size(), b[f].grid.size()); ++i) {
      d = std::max(d, std::abs(a[f].grid[i].deviation_um - b[f].grid[i].deviation_um));
      largest_value = std::max(largest_value, std::abs(b[f].grid[i].deviation_um));
    }
  }
  return d;
}

// The paper's gear sits inside the CAFXZY's strokes on this path (the test would say nothing otherwise).
TEST(ChainProcess, CafxzyPathIsWithinItsStrokesAndItsInverseKinematicsIsTheClosedForm) {
  const machine::MachineModel model = test::machine_with({});
  const grinding::ChainProcess process(cafxzy(), model, test::kDatumZ);
  for (const auto& pp : test::paper_setup().path().sample(5.0)) {
    const machine::AxisValues theta = process.machine_axes(pp);
    EXPECT_FALSE(cafxzy().outside_stroke(theta)) << cafxzy().outside_stroke(theta)->message;
    machine::AxisPose q = pp.q;
    q.z += test::kDatumZ;
    EXPECT_LT((theta.v - cafxzy_axes(q)).cwiseAbs().maxCoeff(), 1e-10);
  }
}

// A pose the axes cannot reach: the point and the axis named.
TEST(ChainProcess, PathOutsideAStrokeIsRefusedNamingThePointAndTheAxis) {
  std::array<std::optional<machine::Interval>, machine::kAxisCount> strokes;
  strokes[static_cast<int>(Axis::Y)] = machine::Interval{-50.0, 50.0};
  const machine::KinematicChain& narrow = cafxzy().with_strokes(strokes);
  const machine::MachineModel model = test::machine_with({});
  EXPECT_NO_THROW(grinding::ChainProcess(cafxzy(), model, test::kDatumZ).check_path(test::paper_setup().path()));
  try {
    grinding::ChainProcess(narrow, model, test::kDatumZ).check_path(test::paper_setup().path());
    ADD_FAILURE() << "a Y stroke of ±50 mm cannot reach the tilted gear's face width";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("CAFXZY chain, space "), std::string::npos) << m;
    EXPECT_NE(m.find("Y = "), std::string::npos) << m;
    EXPECT_NE(m.find("is outside its stroke [-50, 50] mm"), std::string::npos) << m;
  }
}

// All the components of one axis at once (constant, random ±10…50 µm / ±20…100 µrad), axis by axis: the library's
// chain and the hand-written one give the same flank deviations on teeth 1 and 18 to 1e-4 µm (exact method), and
// the first-order method (the chain's error Jacobian) differs from them by second-order terms only.
/// All the components of each axis of `chain` at once against the hand-written chain `hand`, axis by axis.
void expect_hand_written_flanks(const machine::KinematicChain& chain, HandChain hand, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> magnitude(1.0, 5.0), sign(-1.0, 1.0);
  for (const Axis axis : machine::kAxes) {
    ErrorVector e = ErrorVector::Zero();
    for (int k = 0; k < machine::kComponentCount; ++k) {
      if (chain.info(machine::component_at(k)).axis != axis) continue;
      const bool angle = machine::info(machine::component_at(k)).quantity == machine::Quantity::Angle;
      e(k) = (sign(rng) < 0 ? -1.0 : 1.0) * magnitude(rng) * (angle ? 20e-6 : 10e-3);
    }
    const machine::MachineModel model = machine_of(e);
    const grinding::ChainProcess library(chain, model, test::kDatumZ);
    const auto expected = test::simulate(by_hand(e, hand), grinding::Method::Exact);
    double largest = 0.0;
    EXPECT_LT(largest_difference(test::simulate(library, grinding::Method::Exact), expected, largest), 1e-4)
        << chain.name() << " " << machine::axis_name(axis);
    EXPECT_GT(largest, 1.0) << chain.name() << " " << machine::axis_name(axis) << ": the errors must show on the flanks";
    // First order: what it leaves out is second order in the errors (≤ 0.05 µm at 100 µrad; a tenth of the errors
    // leaves a hundredth of it).
    const double first_order = largest_difference(test::simulate(library, grinding::Method::Linear), expected, largest);
    EXPECT_LT(first_order, 0.05) << chain.name() << " " << machine::axis_name(axis);
    const machine::MachineModel tenth_model = machine_of(0.1 * e);
    const grinding::ChainProcess tenth(chain, tenth_model, test::kDatumZ);
    const double tenth_first_order = largest_difference(test::simulate(tenth, grinding::Method::Linear),
                                                        test::simulate(by_hand(0.1 * e, hand), grinding::Method::Exact),
                                                        largest);
    EXPECT_LT(tenth_first_order, 0.02 * first_order + 1e-4) << chain.name() << " " << machine::axis_name(axis);
  }
}

TEST(ChainProcess, ConstantErrorOfEachAxisGivesTheHandWrittenFlankDeviations) {
  expect_hand_written_flanks(cafxzy(), cafxzy_hand, 4242);
}

// The same on the CXFZAY (the radial axis on the workpiece side): the X table carries the C table, so its errors move
// the gear, and the swivel's axis line passes 120 mm above the wheel centre.
TEST(ChainProcess, CxfzayConstantErrorOfEachAxisGivesTheHandWrittenFlankDeviations) {
  expect_hand_written_flanks(cxfzay(), cxfzay_hand, 4343);
}

// The paper's gear sits inside the CXFZAY's strokes on this path, and its inverse kinematics is the closed form.
TEST(ChainProcess, CxfzayPathIsWithinItsStrokesAndItsInverseKinematicsIsTheClosedForm) {
  const machine::MachineModel model = test::machine_with({});
  const grinding::ChainProcess process(cxfzay(), model, test::kDatumZ);
  EXPECT_NO_THROW(process.check_path(test::paper_setup().path()));
  for (const auto& pp : test::paper_setup().path().sample(5.0)) {
    const machine::AxisValues theta = process.machine_axes(pp);
    EXPECT_FALSE(cxfzay().outside_stroke(theta)) << cxfzay().outside_stroke(theta)->message;
    machine::AxisPose q = pp.q;
    q.z += test::kDatumZ;
    EXPECT_LT((theta.v - cxfzay_axes(q)).cwiseAbs().maxCoeff(), 1e-10);
  }
}

// A positioning error Δγ of the workpiece spindle turns the gear: every right flank reads −r_b cos β_b Δγ, every
// left flank +r_b cos β_b Δγ, whichever side the swivel is on (the CFXZAY's test_simulation has the same law).
TEST(ChainProcess, SpindleZeroErrorTurnsTheGearOnAnyLayout) {
  const machine::MachineModel model = test::machine_with({machine::ErrorSource::constant(ComponentId::E_COC, 20.0, "urad")});
  const grinding::ChainProcess process(cafxzy(), model, test::kDatumZ);
  const auto& g = test::paper_setup().geometry();
  const double expected = 0.5 * g.base_diameter_mm() * std::cos(g.base_helix_angle()) * 20e-6 * 1e3; // 4.60 µm
  for (const auto& ft : test::simulate(process, grinding::Method::Exact))
    for (const auto& p : ft.grid) EXPECT_NEAR(p.deviation_um, -side_sign(ft.flank) * expected, 0.01);
}

// ChainProcess keeps, per thread, the joints that did not move since that thread's last point (machine::ChainData):
// its results must not depend on which points a thread saw before. Position-dependent errors on the axes that move
// along the CAFXZY's strokes (Y, Z; C) and on X; exact and linear, 1 thread against 3: the same bits.
TEST(ChainProcess, ResultsAreTheSameAtAnyThreadCount) {
  using machine::ErrorSource;
  const machine::MachineModel model = test::machine_with(
      {ErrorSource::polynomial(ComponentId::delta_zz, {3.0, 0.01, 2e-5}, "um", "mm"),
       ErrorSource::polynomial(ComponentId::epsilon_xy, {5.0, -0.03}, "urad", "mm"),
       ErrorSource::polynomial(ComponentId::delta_yx, {-2.0, 0.004}, "um", "mm"),
       ErrorSource::constant(ComponentId::epsilon_zc, 12.0, "urad"),
       ErrorSource::constant(ComponentId::E_BOA, 9.0, "urad")});
  const grinding::ChainProcess process(cafxzy(), model, test::kDatumZ);
  for (const grinding::Method method : {grinding::Method::Exact, grinding::Method::Linear}) {
    std::vector<std::vector<grinding::FlankTopology>> runs;
    for (const int threads : {1, 3}) {
      grinding::SimulationOptions o;
      o.method = method;
      o.teeth = {1, 7, 18};
      o.profile_points = 12;
      o.helix_points = 12;
      o.threads = threads;
      runs.push_back(grinding::simulate_topology(test::paper_setup(), process, o));
    }
    double largest = 0.0;
    ASSERT_EQ(runs[0].size(), runs[1].size());
    for (std::size_t f = 0; f < runs[0].size(); ++f) {
      ASSERT_EQ(runs[0][f].grid.size(), runs[1][f].grid.size());
      for (std::size_t i = 0; i < runs[0][f].grid.size(); ++i) {
        EXPECT_EQ(runs[0][f].grid[i].deviation_um, runs[1][f].grid[i].deviation_um) << "flank " << f << ", point " << i;
        largest = std::max(largest, std::abs(runs[0][f].grid[i].deviation_um));
      }
    }
    EXPECT_GT(largest, 1.0) << "µm: the errors must show for the comparison to mean anything";
  }
}

} // namespace
} // namespace geartopo
