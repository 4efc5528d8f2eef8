// Surface view: meshes with per-vertex values in the diverging colour map. Checks here; drawing in scene3d.cpp.

#include "geartopo/render/surface_view.hpp"
#include "geartopo/render/colour_map.hpp"
#include "detail/layout.hpp"
#include "detail/scene3d.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace geartopo::render {

RenderResult render_surface_view(const SurfaceView& view, const std::filesystem::path& png) {
  using detail::require;
  require(!view.meshes.empty(), "surface view '" + view.title + "': no data point (no mesh)");
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (std::size_t m = 0; m < view.meshes.size(); ++m) {
    const SurfaceMesh& mesh = view.meshes[m];
    const std::string which = "surface view: mesh " + std::to_string(m);
    require(mesh.vertices.cols() > 0 && mesh.faces.cols() > 0, which + " has no vertex or no face (no data point)");
    require(mesh.vertices.allFinite(), which + " has non-finite vertices");
    require(mesh.faces.minCoeff() >= 0 && mesh.faces.maxCoeff() < mesh.vertices.cols(),
            which + " has a face index outside 0 … " + std::to_string(mesh.vertices.cols() - 1));
    require(mesh.values.size() == 0 || mesh.values.size() == mesh.vertices.cols(),
            which + " has " + std::to_string(mesh.values.size()) + " values for " +
                std::to_string(mesh.vertices.cols()) + " vertices");
    require(mesh.values.allFinite(), which + " has non-finite values");
    require(mesh.opacity > 0.0 && mesh.opacity <= 1.0, which + ": opacity must be in (0, 1]");
    if (mesh.values.size() > 0) {
      lo = std::min(lo, mesh.values.minCoeff());
      hi = std::max(hi, mesh.values.maxCoeff());
    }
  }
  const bool has_values = lo <= hi;
  const Range colour = has_values ? colour_range(lo, hi, view.scale) : Range{};

  detail::Scene3D scene(view.size, detail::font_px(view.size, view.font_px));
  for (const SurfaceMesh& mesh : view.meshes) {
    std::vector<Rgb> vertex_colours;
    for (Eigen::Index i = 0; i < mesh.values.size(); ++i) vertex_colours.push_back(colour_for(mesh.values(i), colour));
    scene.add_mesh(mesh.vertices, mesh.faces, vertex_colours, mesh.colour, mesh.opacity, true, mesh.edges);
  }
  if (view.camera)
    scene.set_camera(*view.camera);
  else
    scene.set_auto_camera(view.view_direction, view.view_up, view.parallel, 1.05);
  for (const SurfaceLabel& label : view.labels) {
    require(label.at.allFinite(), "surface view: label '" + label.text + "' has a non-finite position");
    detail::OverlayText t;
    t.text = label.text;
    t.px = static_cast<int>(std::lround(1.1 * detail::font_px(view.size, view.font_px)));
    t.bold = true;
    t.box = true;
    t.h = HAlign::centre;
    t.v = detail::VAlign::bottom;
    t.y = 0.6F * static_cast<float>(t.px); // above the dot
    scene.add_label(label.at, t);
  }
  if (!view.labels.empty()) { // a dot at each labelled point: the label's text stands just above it
    std::vector<Eigen::Vector3d> at;
    for (const SurfaceLabel& label : view.labels) at.push_back(label.at);
    scene.add_points(at, std::vector<Rgb>(at.size(), colours::black), 0.6 * detail::font_px(view.size, view.font_px));
  }
  scene.set_title(view.title);
  scene.set_caption(view.caption);
  if (has_values) scene.set_colour_bar(colour, detail::axis_label(view.scale.title, view.scale.unit));
  scene.render(png);
  RenderResult result;
  if (has_values) result.colour_range = colour;
  return result;
}

} // namespace geartopo::render
