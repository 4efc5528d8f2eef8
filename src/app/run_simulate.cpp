#include "app/simulate_command.hpp"

#include "app/commands.hpp"
#include "app/messages.hpp"
#include "app/parsers.hpp"

#include "geartopo/files/output_folder.hpp"
#include "geartopo/grinding/flank_mesh.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/surfaces/triangle_mesh.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <tuple>

namespace geartopo::app {

int run_simulate(const SimulateOptions& opt) {
  const auto job_start = std::chrono::steady_clock::now();
  output::RunFiles files{{opt.scene}, {"topology.csv", "traces.csv"}};
  if (!opt.dense.empty()) files.outputs.emplace_back("dense.csv");
  output::OutputFolder folder(opt.out, files); // locked and staged before any work: a second run is refused now
  const Workbench wb(opt.scene);
  print_notes(wb);
  grinding::SimulationOptions so = workbench::scene_simulation(wb.scene.grid);
  so.method = opt.method == "linear" ? grinding::Method::Linear : grinding::Method::Exact;
  // Given but empty (`--teeth ""`) is refused by parse_teeth, not taken as "not given".
  if (opt.teeth_given) so.teeth = parse_teeth(opt.teeth, wb.setup.geometry().teeth());
  if (!opt.dense.empty()) std::tie(so.dense_rows, so.dense_cols) = parse_grid_size(opt.dense);
  const long long flanks = 2LL * static_cast<long long>(so.teeth.empty() ? wb.setup.geometry().teeth() : so.teeth.size());
  const long long points = flanks * (static_cast<long long>(so.rows) * so.cols +
                                     static_cast<long long>(so.dense_rows) * so.dense_cols + so.profile_points +
                                     so.helix_points);
  // The flag's own bound is per flank; over all flanks the simulator's bound decides. Checked here, so that
  // `--dense 2000x2000` on 70 flanks is bad usage of the flag (exit 2), not a failure of the simulation.
  if (!opt.dense.empty() && points > grinding::kMaxPointsPerSimulation)
    throw CLI::ValidationError("--dense", fmt::format("'{}' makes {} points on {} flanks, more than the {} a "
                                                      "simulation may hold: choose a coarser grid or fewer --teeth",
                                                      opt.dense, points, flanks, grinding::kMaxPointsPerSimulation));
  print_work_estimate(points, flanks, so.method == grinding::Method::Exact);
  SimulationWatch progress("simulate", flanks, so.threads, opt.max_time_s, job_start,
                           "a coarser grid (measurement.rows/cols, --dense) or fewer --teeth, or raise --max-time-s");
  so.progress = progress.callback();
  const auto topo = grinding::simulate_topology(wb.setup, wb.process(), so);
  progress.finish();
  const std::filesystem::path out(opt.out);
  grinding::write_topology_csv(out / "topology.csv", topo);
  grinding::write_traces_csv(out / "traces.csv", topo);
  if (so.dense_rows > 0) grinding::write_topology_csv(out / "dense.csv", topo, grinding::GridKind::Dense);
  for (const auto& ft : topo)
    surfaces::write_mesh(grinding::flank_mesh(wb.setup.flanks(), ft),
                         out / "meshes" / fmt::format("tooth{:02d}_{}.ply", ft.tooth, gears::to_string(ft.flank)));

  double lo = 1e300, hi = -1e300;
  std::cout << fmt::format("{} flanks simulated ({} method), grid {}×{}; deviations in µm, plus material:\n",
                           topo.size(), opt.method, so.rows, so.cols);
  std::cout << fmt::format("  {:>5} {:<5} {:>9} {:>9} {:>9}\n", "tooth", "flank", "min", "max", "range");
  for (const auto& ft : topo) {
    const auto [mn, mx] = std::minmax_element(ft.grid.begin(), ft.grid.end(),
                                              [](const auto& a, const auto& b) { return a.deviation_um < b.deviation_um; });
    lo = std::min(lo, mn->deviation_um), hi = std::max(hi, mx->deviation_um);
    std::cout << fmt::format("  {:>5} {:<5} {:>9.2f} {:>9.2f} {:>9.2f}\n", ft.tooth, gears::to_string(ft.flank),
                             mn->deviation_um, mx->deviation_um, mx->deviation_um - mn->deviation_um);
  }
  std::cout << fmt::format("all flanks: {:.2f} … {:.2f} µm\nwrote {}/topology.csv, traces.csv{}, meshes/*.ply\n", lo, hi,
                           out.string(), so.dense_rows > 0 ? ", dense.csv" : "");
  finish_output_folder(folder);
  return 0;
}

} // namespace geartopo::app
