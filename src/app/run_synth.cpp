// geartopo synth's work (synth_command.hpp): the measurement of a gear ground on the truth scene, written atomically.
#include "app/synth_command.hpp"

#include "app/commands.hpp"
#include "app/parsers.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/input_registry.hpp"
#include "geartopo/files/output_folder.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/pipeline/synth_corrections.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <optional>

namespace geartopo::app {

int run_synth(const SynthFlags& opt) {
  const Workbench wb(opt.scene);
  diagnosis::SynthOptions so;
  so.teeth = parse_teeth(opt.teeth, wb.setup.geometry().teeth());
  so.rows = wb.scene.grid.rows;
  so.cols = wb.scene.grid.cols;
  so.noise_um = opt.noise;
  so.seed = opt.seed;
  const auto table = pipeline::synth_corrections(wb, opt.corrections, opt.stroke_scatter, opt.seed);
  std::optional<compensation::CompensatedProcess> corrected;
  if (table) corrected.emplace(wb.process(), *table);
  const grinding::GrindingProcess& process =
      corrected ? static_cast<const grinding::GrindingProcess&>(*corrected) : wb.process();
  // Every other command's --out is a folder: a folder here gets the measurement under a fixed name.
  std::filesystem::path file(opt.out);
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec) || opt.out.back() == '/')
    file /= opt.format == "klingelnberg" ? "measured.mka" : opt.format == "traces" ? "traces.csv" : "measured.csv";
  // Before any work: the scene or the corrections read above are never replaced, and a name too long for the
  // file system or a file where a folder must be is refused in words, not as a std::filesystem error.
  output::check_name_lengths(file);
  output::check_not_an_input(file);
  if (file.has_parent_path()) {
    const auto folder = file.parent_path();
    if (std::filesystem::exists(folder, ec) && !std::filesystem::is_directory(folder, ec))
      throw output::OutputError(file, folder.string() + " is a file, not a folder (a --out ending in '/' names a folder)");
    std::filesystem::create_directories(folder, ec);
    if (ec) throw output::OutputError(file, "cannot create its folder " + folder.string() + ": " + ec.message());
  }
  std::size_t points = 0;
  if (opt.format == "traces") {
    const auto topo = diagnosis::synthesize_traces(wb.setup, process, so, wb.scene.grid.profile_points,
                                                   wb.scene.grid.helix_points);
    for (const auto& ft : topo) points += ft.profile.size() + ft.helix.size();
    output::write_atomically(file, [&](std::ostream& out) { grinding::write_traces_csv(out, topo); });
  } else {
    const auto rows = diagnosis::synthesize(wb.setup, process, so);
    points = rows.size();
    output::write_atomically(file, [&](std::ostream& out) {
      if (opt.format == "klingelnberg")
        measurement::write_klingelnberg(out, wb.setup.geometry(), rows);
      else
        grinding::write_topology_rows(out, rows);
    });
  }
  std::string ground;
  if (!opt.corrections.empty()) ground += ", with the corrections of " + opt.corrections;
  if (opt.stroke_scatter) ground += ", stroke scatter";
  std::cout << fmt::format("wrote {} ({} points, noise {} µm, seed {}{})\n", file.string(), points, opt.noise,
                           opt.seed, ground);
  return 0;
}

} // namespace geartopo::app
