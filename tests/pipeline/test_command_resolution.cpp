// The command resolution (docs/compensation.md, "Command resolution") on the default scene: why the predicted profile
// form f_fα rose after compensation (0.13 → 0.45 µm in every sample, "−242 %"), and that it no longer does.
//
// The cause: the C corrections were rounded entry by entry to machine.resolution (0.1 mdeg = 1.745 µrad). Along a
// stroke they vary by several µrad, so the rounded table steps by one unit a few times per stroke, and a helical
// flank's contact line carries each step across the profile: a profile point at roll length ξ and face position z is
// ground at stroke position z − Δz(ξ) (FormWheel::contact_offset_mm), so a C error e(Z) along the stroke moves it by
// r_b cos β_b · e(z − Δz(ξ)) along the normal (a rigid turn of the gear, ISO 21771). The first test rebuilds that
// per-entry rounding and checks the simulated change of every profile point against this formula: the rise is the
// C staircase, not the interpolation or the simulation. The others check the model the prediction uses now: the
// controller rounds the setpoint, command plus correction, each row taking its mean rounding error over its stretch of
// the stroke (pipeline::rounded_to_resolution, against a brute-force mean on a made-up table); C sweeps about 1 165
// units per mm of Z on the default scene, so its rounding averages out and f_fα after is that of the corrections as
// computed, while A, which the stroke holds still, keeps the nearest multiple.
#include "geartopo/pipeline/monte_carlo.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <vector>

using namespace geartopo;

namespace command_resolution_test { // its own: one unity build with the other Monte Carlo tests
namespace {

const workbench::Workbench& default_scene() {
  static const workbench::Workbench wb(std::filesystem::path(GEARTOPO_SOURCE_DIR) / "scenes/skmc1200w-mn14-z35.yaml");
  return wb;
}

/// The flank method's corrections as `compensate` computes them (every 2 mm of every stroke).
const compensation::CorrectionTable& default_corrections() {
  static const compensation::CorrectionTable t = [] {
    const auto& wb = default_scene();
    return compensation::compute_corrections(wb.setup, wb.process(), {wb.machine, wb.scene.machine.datum_face_z_mm}, {});
  }();
  return t;
}

/// The table with only axis `axis` changed by `change(row)`.
template <class Change>
compensation::CorrectionTable with_axis(const compensation::CorrectionTable& t, int axis, Change change) {
  auto rows = t.rows();
  for (auto& r : rows) r.correction(axis) = change(r);
  return compensation::CorrectionTable(std::move(rows));
}

/// Tooth 1 of the default scene (grid and 100-point traces) ground with `table` on the scene's machine.
std::vector<grinding::FlankTopology> tooth1(const compensation::CorrectionTable& table) {
  const auto& wb = default_scene();
  grinding::SimulationOptions so;
  so.rows = wb.scene.grid.rows;
  so.cols = wb.scene.grid.cols;
  so.profile_points = wb.scene.grid.profile_points;
  so.helix_points = wb.scene.grid.helix_points;
  so.teeth = {1};
  const compensation::CompensatedProcess ground(wb.process(), table);
  return grinding::simulate_topology(wb.setup, ground, so);
}

/// |worst| profile form deviation f_fα of the flanks (µm, ISO 1328-1, transverse: the report's value).
double profile_form_um(const std::vector<grinding::FlankTopology>& topo) {
  const auto& wb = default_scene();
  const auto iso = workbench::evaluate_iso(wb.setup.geometry(), wb.setup.ranges(), topo);
  for (const auto& q : iso.evaluation.classification.quantities)
    if (q.quantity == evaluation::Quantity::ProfileForm) return std::abs(q.worst_value_um);
  ADD_FAILURE() << "no f_fα";
  return 0.0;
}

constexpr int kC = 4; // axis index of C in a correction (X, Y, Z, A, C)

} // namespace

// Rounded entry by entry (the model the prediction used), the C corrections of the default scene change every profile
// point of tooth 1 by r_b cos β_b times the rounding error of C at the stroke position that grinds it, within 0.01 µm
// (first order in 1.7 µrad: the rest is 10⁻⁶ µm); that staircase raises f_fα by more than 0.25 µm — a unit of C is
// r_b cos β_b · 1.745 µrad = 0.40 µm along the normal, 0.46 µm transverse.
TEST(CommandResolution, RoundedCEntriesStepAcrossTheProfileOfAHelicalFlank) {
  const auto& wb = default_scene();
  const double q = wb.scene.machine.uncertainty.resolution(kC);
  ASSERT_NEAR(q, 0.1e-3 * std::numbers::pi / 180.0, 1e-15) << "the scene's C resolution, 0.1 mdeg";
  const auto& nominal = default_corrections();
  const auto per_entry = with_axis(nominal, kC, [q](const auto& r) { return q * std::round(r.correction(kC) / q); });
  const auto exact = tooth1(nominal), stepped = tooth1(per_entry);
  const auto& g = wb.setup.geometry();
  const double unit_um = 0.5 * g.base_diameter_mm() * std::cos(g.base_helix_angle()) * q * 1e3; // mm·rad → µm
  ASSERT_EQ(exact.size(), 2u);
  for (size_t f = 0; f < exact.size(); ++f) {
    const auto& flank = exact[f];
    const int space = grinding::space_of(flank.tooth, flank.flank, g.teeth());
    std::vector<double> predicted_um, change_um;
    for (size_t i = 0; i < flank.profile.size(); ++i) {
      const auto& p = flank.profile[i];
      const double z_stroke = p.z_mm - wb.setup.wheel().contact_offset_mm(flank.flank, p.roll_length_mm);
      const double error_rad = per_entry.at(space, z_stroke)(kC) - nominal.at(space, z_stroke)(kC);
      predicted_um.push_back(0.5 * g.base_diameter_mm() * std::cos(g.base_helix_angle()) * error_rad * 1e3);
      change_um.push_back(stepped[f].profile[i].deviation_um - p.deviation_um);
    }
    // The sense of a turn of the gear is + on one flank, − on the other: fixed by the largest predicted change.
    size_t largest = 0;
    for (size_t i = 0; i < predicted_um.size(); ++i)
      if (std::abs(predicted_um[i]) > std::abs(predicted_um[largest])) largest = i;
    ASSERT_GT(std::abs(predicted_um[largest]), 0.25 * unit_um) << "flank " << f << ": no step near its profile";
    const double sign = change_um[largest] * predicted_um[largest] > 0.0 ? 1.0 : -1.0;
    double worst = 0.0;
    for (size_t i = 0; i < predicted_um.size(); ++i) {
      EXPECT_NEAR(change_um[i], sign * predicted_um[i], 0.01) << "flank " << f << " point " << i;
      worst = std::max(worst, std::abs(change_um[i] - sign * predicted_um[i]));
    }
    const double lo = *std::min_element(predicted_um.begin(), predicted_um.end());
    const double hi = *std::max_element(predicted_um.begin(), predicted_um.end());
    // The profile spans stroke positions on both sides of a step: the change runs over most of a unit.
    EXPECT_GT(hi - lo, 0.6 * unit_um) << "flank " << f;
    std::cout << "flank " << f << ": the C staircase moves the profile by " << lo << " … " << hi << " µm (a unit: "
              << unit_um << " µm), simulated against r_b cos β_b·e(z − Δz(ξ)) within " << worst << " µm\n";
  }
  const double before = profile_form_um(exact), after = profile_form_um(stepped);
  std::cout << "f_fα of tooth 1: " << before << " µm with the corrections as computed, " << after
            << " µm with C rounded entry by entry\n";
  EXPECT_GT(after - before, 0.25);
}

// The setpoint model against brute force: rows every 2 mm whose commanded C moves 0, 0.4 or 3.3 units between rows
// (a held axis, a slow and a faster one) and corrections spread over several units. Each row's applied correction is
// its own plus the rounding error of the setpoint, command + correction, averaged over the row's stretch (midpoint to
// midpoint, the command linear in between, the row's own command on the grid: programmed positions are, and the
// gear before compensation is not rounded either) — summed here over 200 001 setpoints per half-stretch. The brute force's
// own error is below 10⁻⁴ of a unit (a jump of one unit per 200 000th of the sweep); allowed: 2·10⁻⁴.
TEST(CommandResolution, EachRowTakesTheSetpointsRoundingErrorAveragedOverItsStretch) {
  const double q = 0.1e-3 * std::numbers::pi / 180.0; // 0.1 mdeg
  for (const double units_per_row : {0.0, 0.4, 3.3}) {
    std::vector<compensation::CorrectionRow> rows;
    for (int k = 0; k <= 10; ++k) {
      compensation::CorrectionRow r;
      r.space = 1;
      r.z_stroke_mm = 2.0 * k;
      r.machine_axes.c = 1.0 + units_per_row * q * k;
      r.correction(kC) = q * (2.3 * std::sin(0.7 * k) + 0.37 * k); // several units, at every fraction of one
      rows.push_back(r);
    }
    const compensation::CorrectionTable table(rows);
    machine::Vector5d resolution = machine::Vector5d::Zero();
    resolution(kC) = q;
    const auto applied = pipeline::rounded_to_resolution(table, resolution);
    for (size_t i = 0; i < rows.size(); ++i) {
      double sum = 0.0, length = 0.0;
      for (const long j : {static_cast<long>(i) - 1, static_cast<long>(i) + 1}) {
        if (j < 0 || j >= static_cast<long>(rows.size())) continue;
        const double half = 0.5 * std::abs(rows[static_cast<size_t>(j)].z_stroke_mm - rows[i].z_stroke_mm);
        const double dc = 0.5 * (rows[static_cast<size_t>(j)].machine_axes.c - rows[i].machine_axes.c);
        constexpr int kSteps = 200000;
        double s = 0.0;
        for (int k = 0; k <= kSteps; ++k) {
          const double u = (dc * k / kSteps + rows[i].correction(kC)) / q; // the row's command on the grid
          s += (k == 0 || k == kSteps ? 0.5 : 1.0) * (std::round(u) - u);
        }
        sum += half * s / kSteps, length += half;
      }
      const double applied_error = (applied.rows()[i].correction(kC) - rows[i].correction(kC)) / q;
      EXPECT_NEAR(applied_error, sum / length, 2e-4) << units_per_row << " units per row, row " << i;
      if (units_per_row == 0.0) {
        EXPECT_NEAR(applied.rows()[i].correction(kC), q * std::round(rows[i].correction(kC) / q), 1e-12 * q);
      }
    }
  }
}

// On the default scene C sweeps ≈ 2 330 units of 0.1 mdeg between rows: its rounding averages to below 10⁻³ of a unit
// on every row, while A, standing still, keeps the nearest multiple. Ground with it, tooth 1's f_fα is that of the
// corrections as computed, within 0.005 µm.
TEST(CommandResolution, TheControllerRoundsTheSetpointSoCsRoundingAveragesOut) {
  const auto& wb = default_scene();
  const auto& res = wb.scene.machine.uncertainty.resolution;
  machine::Vector5d only_c = machine::Vector5d::Zero(), only_a = machine::Vector5d::Zero();
  only_c(kC) = res(kC);
  only_a(3) = res(3);
  const auto& nominal = default_corrections();
  const auto applied_c = pipeline::rounded_to_resolution(nominal, only_c);
  const auto applied_a = pipeline::rounded_to_resolution(nominal, only_a);
  const auto& rows = nominal.rows();
  ASSERT_GT(rows.size(), 1000u);
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    EXPECT_LT(std::abs(applied_c.rows()[i].correction(kC) - r.correction(kC)), 1e-3 * res(kC)) << "row " << i;
    EXPECT_NEAR(applied_a.rows()[i].correction(3), res(3) * std::round(r.correction(3) / res(3)), 1e-12 * res(3))
        << "row " << i << ": A stands still";
  }
  const double applied = profile_form_um(tooth1(applied_c)), computed = profile_form_um(tooth1(nominal));
  std::cout << "f_fα of tooth 1: " << computed << " µm with the corrections as computed, " << applied
            << " µm with the controller rounding C's setpoint\n";
  EXPECT_NEAR(applied, computed, 0.005);
}

} // namespace command_resolution_test
