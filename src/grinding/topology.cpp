#include "geartopo/grinding/topology.hpp"

#include <mutex>
#include "geartopo/core/limits.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/core/parallel.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace geartopo::grinding {
namespace {

std::vector<double> evenly(double a, double b, int n) {
  std::vector<double> out(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) out[static_cast<size_t>(i)] = n == 1 ? 0.5 * (a + b) : a + (b - a) * i / (n - 1);
  return out;
}

std::vector<GridPoint> grid(const FlankDeviation& dev, const gears::GearGeometry& g, int tooth, geartopo::Flank flank,
                            const std::vector<double>& xis, const std::vector<double>& zs, Method m,
                            const std::function<void()>& keep_going) {
  std::vector<GridPoint> out;
  out.reserve(xis.size() * zs.size());
  for (size_t r = 0; r < xis.size(); ++r) {
    if (keep_going) keep_going(); // once a row: a 1000 × 1000 flank takes minutes
    for (size_t c = 0; c < zs.size(); ++c)
      out.push_back({static_cast<int>(r + 1), static_cast<int>(c + 1), xis[r], g.diameter_at_roll_length(xis[r]), zs[c],
                     units::um_from_mm(dev.at(tooth, flank, xis[r], zs[c], m).deviation_mm)});
  }
  return out;
}

} // namespace

double largest_abs_deviation_um(const std::vector<FlankTopology>& topo) {
  double m = 0.0;
  for (const auto& ft : topo)
    for (const auto& p : ft.grid) m = std::max(m, std::abs(p.deviation_um));
  return m;
}

std::vector<double> grid_roll_lengths(const gears::EvaluationRanges& r, int rows) {
  return evenly(r.xi_eval_start_mm, r.xi_eval_end_mm, rows);
}

std::vector<double> grid_axial_positions(const gears::EvaluationRanges& r, int cols) {
  return evenly(r.z_eval_start_mm, r.z_eval_end_mm, cols);
}

SimulationPoints simulation_points(const GrindingSetup& setup, const SimulationOptions& o) {
  const auto& g = setup.geometry();
  SimulationPoints pts;
  pts.teeth = o.teeth;
  if (pts.teeth.empty())
    for (int t = 1; t <= g.teeth(); ++t) pts.teeth.push_back(t);
  // The bounds every caller is held to (core/limits.hpp), before anything is allocated.
  limits::require(limits::teeth_refusal(pts.teeth, g.teeth()), "simulate_topology: teeth");
  limits::require(limits::grid_refusal(o.rows, o.cols, 2), "simulate_topology: rows × cols");
  limits::require(limits::trace_points_refusal(o.profile_points, o.helix_points), "simulate_topology: profile_points, helix_points");
  if (o.dense_rows < 0 || o.dense_cols < 0 || (o.dense_rows > 0) != (o.dense_cols > 0))
    throw std::invalid_argument(fmt::format("simulate_topology: dense_rows × dense_cols: {} × {} is not a grid: both 0 "
                                            "(none) or both ≥ 1", o.dense_rows, o.dense_cols));
  const long long per_flank = static_cast<long long>(o.rows) * o.cols + static_cast<long long>(o.dense_rows) * o.dense_cols +
                              o.profile_points + o.helix_points;
  if (per_flank > kMaxPointsPerFlank || per_flank * 2 * static_cast<long long>(pts.teeth.size()) > kMaxPointsPerSimulation)
    throw std::invalid_argument(fmt::format("simulate_topology: points: {} per flank on {} flanks is more than a "
                                            "simulation may hold ({} per "
                                            "flank, {} in all): choose a coarser grid",
                                            per_flank, 2 * pts.teeth.size(), kMaxPointsPerFlank, kMaxPointsPerSimulation));

  const auto& r = setup.ranges();
  pts.rows = grid_roll_lengths(r, o.rows);
  pts.cols = grid_axial_positions(r, o.cols);
  pts.profile_roll_lengths = evenly(r.xi_active_start_mm, r.xi_active_end_mm, o.profile_points);
  pts.helix_z = evenly(0.0, g.spec().face_width_mm, o.helix_points);
  pts.profile_z_mm = 0.5 * g.spec().face_width_mm;
  pts.helix_roll_length_mm = 0.5 * (r.xi_eval_start_mm + r.xi_eval_end_mm);
  if (o.dense_rows > 0 && o.dense_cols > 0) {
    pts.dense_rows = grid_roll_lengths(r, o.dense_rows);
    pts.dense_cols = grid_axial_positions(r, o.dense_cols);
  }
  return pts;
}

std::vector<FlankTopology> simulate_topology(const GrindingSetup& setup, const GrindingProcess& process,
                                             const SimulationOptions& o) {
  const auto& g = setup.geometry();
  const SimulationPoints pts = simulation_points(setup, o);
  const auto& teeth = pts.teeth;
  const auto &rows = pts.rows, &cols = pts.cols, &prof_xi = pts.profile_roll_lengths, &helix_z = pts.helix_z;
  const double prof_z = pts.profile_z_mm, helix_xi = pts.helix_roll_length_mm;
  const FlankDeviation dev(setup.flanks(), setup.wheel(), setup.path(), process);

  std::vector<FlankTopology> out(2 * teeth.size());
  // Reports in order: the count is raised and reported under one lock, so a progress display (or a Python callback,
  // which takes its own lock) never sees 6 before 5.
  std::mutex report;
  long long flanks_done = 0;
  parallel_for(static_cast<int>(out.size()), o.threads, [&](int i) {
    FlankTopology& ft = out[static_cast<size_t>(i)];
    ft.tooth = teeth[static_cast<size_t>(i / 2)];
    ft.flank = i % 2 == 0 ? geartopo::Flank::Left : geartopo::Flank::Right;
    ft.grid = grid(dev, g, ft.tooth, ft.flank, rows, cols, o.method, o.keep_going);
    if (o.keep_going) o.keep_going();
    for (double xi : prof_xi)
      ft.profile.push_back({xi, g.diameter_at_roll_length(xi), prof_z,
                            units::um_from_mm(dev.at(ft.tooth, ft.flank, xi, prof_z, o.method).deviation_mm)});
    for (double z : helix_z)
      ft.helix.push_back({helix_xi, g.diameter_at_roll_length(helix_xi), z,
                          units::um_from_mm(dev.at(ft.tooth, ft.flank, helix_xi, z, o.method).deviation_mm)});
    if (o.keep_going) o.keep_going();
    if (!pts.dense_rows.empty())
      ft.dense = grid(dev, g, ft.tooth, ft.flank, pts.dense_rows, pts.dense_cols, o.method, o.keep_going);
    if (o.progress) {
      const std::lock_guard lock(report);
      o.progress(++flanks_done, static_cast<long long>(out.size()));
    }
  });
  require_all_reached(out);
  attach_design(out, setup.design());
  return out;
}

void attach_design(std::vector<FlankTopology>& topo, const gears::FlankDesign& design) {
  if (design.empty()) return;
  for (auto& ft : topo) {
    for (auto* grid : {&ft.grid, &ft.dense})
      for (auto& p : *grid) p.design_um = design.at_um(ft.flank, p.roll_length_mm, p.z_mm);
    for (auto* trace : {&ft.profile, &ft.helix})
      for (auto& p : *trace) p.design_um = design.at_um(ft.flank, p.roll_length_mm, p.z_mm);
  }
}

void require_all_reached(const std::vector<FlankTopology>& topo) {
  for (const auto& ft : topo) {
    for (const auto& p : ft.grid) require_reached(p.deviation_um, ft.tooth, ft.flank, p.diameter_mm, p.z_mm);
    for (const auto& p : ft.profile) require_reached(p.deviation_um, ft.tooth, ft.flank, p.diameter_mm, p.z_mm);
    for (const auto& p : ft.helix) require_reached(p.deviation_um, ft.tooth, ft.flank, p.diameter_mm, p.z_mm);
    for (const auto& p : ft.dense) require_reached(p.deviation_um, ft.tooth, ft.flank, p.diameter_mm, p.z_mm);
  }
}

} // namespace geartopo::grinding
