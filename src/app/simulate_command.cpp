#include "app/commands.hpp"
#include "app/options.hpp"

#include "geartopo/grinding/flank_mesh.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/surfaces/triangle_mesh.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>

namespace geartopo::app {

void register_simulate_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, out, method = "exact", teeth, dense;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate line-contact profile grinding with the scene's machine "
                                                 "errors; write topology (µm), traces and flank meshes (mm)");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML)")->required();
  cmd->add_option("--out", opt->out, "Output directory (created)")->required();
  cmd->add_option("--method", opt->method, "exact (envelope of the actual wheel poses) or linear (first order)")
      ->check(CLI::IsMember({"exact", "linear"}));
  cmd->add_option("--teeth", opt->teeth, "Teeth to simulate: all (default, or the scene's list) or e.g. 1,18");
  cmd->add_option("--dense", opt->dense, "Also a dense grid per flank, ROWSxCOLS (e.g. 50x100) → dense.csv");
  cmd->callback([&action, opt] {
    action = [opt] {
      const Workbench wb(opt->scene);
      grinding::SimulationOptions so;
      so.method = opt->method == "linear" ? grinding::Method::Linear : grinding::Method::Exact;
      so.teeth = opt->teeth.empty() ? wb.scene.grid.teeth : parse_teeth(opt->teeth, wb.setup.geometry().teeth());
      so.rows = wb.scene.grid.rows;
      so.cols = wb.scene.grid.cols;
      so.profile_points = wb.scene.grid.profile_points;
      so.helix_points = wb.scene.grid.helix_points;
      so.dense_rows = wb.scene.grid.dense_rows;
      so.dense_cols = wb.scene.grid.dense_cols;
      if (!opt->dense.empty()) std::tie(so.dense_rows, so.dense_cols) = parse_grid_size(opt->dense);

      const auto topo = grinding::simulate_topology(wb.setup, wb.process(), so);
      const std::filesystem::path out(opt->out);
      std::filesystem::create_directories(out / "meshes");
      grinding::write_topology_csv(out / "topology.csv", topo);
      grinding::write_traces_csv(out / "traces.csv", topo);
      if (so.dense_rows > 0) grinding::write_topology_csv(out / "dense.csv", topo, grinding::GridKind::Dense);
      for (const auto& ft : topo)
        surfaces::write_mesh(grinding::flank_mesh(wb.setup.flanks(), ft),
                             out / "meshes" / fmt::format("tooth{:02d}_{}.ply", ft.tooth, gears::to_string(ft.flank)));

      double lo = 1e300, hi = -1e300;
      std::cout << fmt::format("{} flanks simulated ({} method), grid {}×{}; deviations in µm, plus material:\n",
                               topo.size(), opt->method, so.rows, so.cols);
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
      return 0;
    };
  });
}

} // namespace geartopo::app
