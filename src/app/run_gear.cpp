#include "app/gear_command.hpp"

#include "app/messages.hpp"

#include "geartopo/files/input_registry.hpp"
#include "geartopo/report/gear_report.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/surfaces/gear_mesh.hpp"
#include "geartopo/surfaces/triangle_mesh.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>

namespace geartopo::app {

int run_gear(const GearOptions& opt) {
  if (!opt.mesh.empty() && !surfaces::is_mesh_extension(opt.mesh))
    throw CLI::ValidationError("--mesh", opt.mesh + ": use a .ply, .obj, .stl or .off file name");
  const scene::Scene sc = scene::load_scene(opt.scene);
  if (!opt.mesh.empty()) output::check_not_an_input(opt.mesh); // the scene (or a table it names) is never replaced
  const gears::GearGeometry g(sc.gear);
  if (opt.json)
    std::cout << report::gear_json(sc, g).dump(2) << "\n";
  else
    std::cout << report::gear_table(sc, g);
  for (const auto& w : g.warnings()) say("geartopo: warning: " + w);
  if (!opt.mesh.empty()) {
    const surfaces::TriangleMesh mesh = surfaces::gear_mesh(g);
    surfaces::write_mesh(mesh, opt.mesh);
    say(fmt::format("geartopo: wrote {} ({} vertices, {} triangles, mm)", opt.mesh, mesh.vertices.cols(),
                    mesh.faces.cols()));
  }
  return 0;
}

} // namespace geartopo::app
