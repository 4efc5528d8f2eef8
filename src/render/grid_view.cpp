// Topology grid view: nominal grid (black), actual grid with the magnified deviation (blue), values at the nodes.
// Geometry and labels are built here; drawing in scene3d.cpp.

#include "geartopo/render/grid_view.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/render/colour_map.hpp"
#include "detail/layout.hpp"
#include "detail/scene3d.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace geartopo::render {

namespace {

using detail::require;

/// The largest 1-2-5 number not above x (> 0).
double nice_floor(double x) {
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  const double r = x / p;
  return (r >= 5.0 ? 5.0 : r >= 2.0 ? 2.0 : 1.0) * p;
}

void check(const GridTopology& g) {
  const Eigen::Index rows = g.deviation.rows();
  const Eigen::Index cols = g.deviation.cols();
  require(rows > 0 && cols > 0, "grid topology '" + g.title + "': no data point (empty grid)");
  require(rows >= 2 && cols >= 2,
          "grid topology: at least 2 x 2 nodes are needed, got " + std::to_string(rows) + " x " + std::to_string(cols));
  require(g.u.rows() == rows && g.u.cols() == cols && g.v.rows() == rows && g.v.cols() == cols,
          "grid topology: u, v and deviation must have the same size (" + std::to_string(rows) + " x " +
              std::to_string(cols) + ")");
  require(g.u.allFinite() && g.v.allFinite() && g.deviation.allFinite(), "grid topology: non-finite u, v or deviation");
  require(g.magnification >= 0.0 && std::isfinite(g.magnification), "grid topology: magnification must be >= 0");
}

} // namespace

double grid_magnification(const GridTopology& g) {
  check(g);
  if (g.magnification > 0.0) return g.magnification;
  // µm; deviations below the colour scale's resolution (0.01 µm) are not magnified further: an ideal machine's 1e-9 µm
  // would otherwise be drawn at ×10¹³ with every node value reading 0.0.
  const double max_dev = std::max(g.deviation.cwiseAbs().maxCoeff(), g.scale.resolution);
  if (max_dev <= 0.0) return 1000.0;
  double target = 0.0; // mm shown for max_dev
  if (g.offset == GridOffset::height) {
    target = 0.15 * std::max(g.u.maxCoeff() - g.u.minCoeff(), g.v.maxCoeff() - g.v.minCoeff());
  } else {
    std::vector<double> spacing;
    for (Eigen::Index i = 0; i + 1 < g.v.rows(); ++i)
      for (Eigen::Index j = 0; j < g.v.cols(); ++j) spacing.push_back(std::abs(g.v(i + 1, j) - g.v(i, j)));
    std::nth_element(spacing.begin(), spacing.begin() + static_cast<std::ptrdiff_t>(spacing.size() / 2), spacing.end());
    target = 0.8 * spacing[spacing.size() / 2];
  }
  if (!(target > 0.0)) return 1000.0;
  return nice_floor(target / (units::mm_from_um(max_dev)));
}

namespace {

/// The grid as drawn: the nominal nodes, and the actual ones with the deviation magnified along the height (3D) or
/// along v (top view, layered by eps above the nominal lines); the extents of u and v.
struct GridDrawing {
  const GridTopology& g;
  double mag;
  Eigen::Index rows, cols;
  bool height;
  double u0, u1, v0, v1, extent, eps;

  GridDrawing(const GridTopology& grid, double magnification)
      : g(grid),
        mag(magnification),
        rows(grid.deviation.rows()),
        cols(grid.deviation.cols()),
        height(grid.offset == GridOffset::height),
        u0(grid.u.minCoeff()),
        u1(grid.u.maxCoeff()),
        v0(grid.v.minCoeff()),
        v1(grid.v.maxCoeff()),
        extent(std::max({u1 - u0, v1 - v0, 1e-9})),
        eps(1e-3 * extent) {} // layering of coincident lines in the top view

  Eigen::Vector3d nominal(Eigen::Index i, Eigen::Index j) const {
    return Eigen::Vector3d(g.u(i, j), g.v(i, j), height ? 0.0 : eps);
  }
  Eigen::Vector3d actual(Eigen::Index i, Eigen::Index j) const {
    const double offset = units::mm_from_um(g.deviation(i, j)) * mag;
    return height ? Eigen::Vector3d(g.u(i, j), g.v(i, j), offset) : Eigen::Vector3d(g.u(i, j), g.v(i, j) + offset, 2 * eps);
  }
  /// The rows, then the columns, of the nominal or the actual grid.
  std::vector<detail::Polyline> lines(bool of_actual) const {
    const auto node = [&](Eigen::Index i, Eigen::Index j) { return of_actual ? actual(i, j) : nominal(i, j); };
    std::vector<detail::Polyline> out;
    for (Eigen::Index i = 0; i < rows; ++i) {
      detail::Polyline l;
      for (Eigen::Index j = 0; j < cols; ++j) l.push_back(node(i, j));
      out.push_back(l);
    }
    for (Eigen::Index j = 0; j < cols; ++j) {
      detail::Polyline l;
      for (Eigen::Index i = 0; i < rows; ++i) l.push_back(node(i, j));
      out.push_back(l);
    }
    return out;
  }
};

/// The surface through the actual nodes, coloured by the deviation.
void add_surface(detail::Scene3D& scene, const GridDrawing& d, const Range& colour, const Eigen::Vector3d& direction) {
  const Eigen::Index rows = d.rows, cols = d.cols;
  Eigen::Matrix3Xd vertices(3, rows * cols);
  std::vector<Rgb> node_colours;
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) {
      Eigen::Vector3d p = d.actual(i, j);
      if (!d.height) p.z() = 0.0;
      // Slightly away from the camera: the grid lines on the surface then always stay in front of it (parallel
      // projection, so nothing moves on screen).
      vertices.col(i * cols + j) = p + 0.004 * d.extent * direction;
      node_colours.push_back(colour_for(d.g.deviation(i, j), colour));
    }
  Eigen::Matrix3Xi faces(3, 2 * (rows - 1) * (cols - 1));
  Eigen::Index f = 0;
  for (Eigen::Index i = 0; i + 1 < rows; ++i)
    for (Eigen::Index j = 0; j + 1 < cols; ++j) {
      const int a = static_cast<int>(i * cols + j), b = a + 1, c = a + static_cast<int>(cols), e = c + 1;
      faces.col(f++) = Eigen::Vector3i(a, b, e);
      faces.col(f++) = Eigen::Vector3i(a, e, c);
    }
  // Translucent in 3D so that the nominal grid stays visible under raised regions.
  scene.add_mesh(vertices, faces, node_colours, colours::white, d.height ? 0.7 : 1.0, false, false);
}

/// The actual nodes as points coloured by the deviation, and (show_values) every value_every-th node's value.
void add_nodes(detail::Scene3D& scene, const GridDrawing& d, const Range& colour, int px) {
  std::vector<Eigen::Vector3d> nodes;
  std::vector<Rgb> node_colours;
  for (Eigen::Index i = 0; i < d.rows; ++i)
    for (Eigen::Index j = 0; j < d.cols; ++j) {
      Eigen::Vector3d p = d.actual(i, j);
      if (!d.height) p.z() = 3 * d.eps;
      nodes.push_back(p);
      node_colours.push_back(colour_for(d.g.deviation(i, j), colour));
    }
  scene.add_points(nodes, node_colours, std::max(6.0, 0.55 * px));

  const int small = static_cast<int>(std::lround(0.72 * px));
  detail::require(d.g.value_every >= 1, "grid topology: value_every must be >= 1");
  if (!d.g.show_values) return;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const auto row = static_cast<Eigen::Index>(k) / d.cols, col = static_cast<Eigen::Index>(k) % d.cols;
    if (row % d.g.value_every != 0 || col % d.g.value_every != 0) continue;
    detail::OverlayText t;
    t.y = 0.45F * static_cast<float>(px);
    t.text = detail::format_value(d.g.deviation(row, col), d.g.value_decimals);
    t.px = small;
    t.h = HAlign::centre;
    t.halo = true;
    t.colour = colours::black;
    scene.add_label(nodes[k], t);
  }
}

/// Where the axes lie: u along the front edge at v_axis, v along the edge seen on the left at u_axis, both at
/// z_axis; `side` is the direction of the v axis's ticks in u.
struct AxesPlacement {
  bool left_is_u0;
  double side, tick, v_axis, u_axis, z_axis;
  int label_px;
  double v_label_w = 0.0; ///< the widest v tick label, px
};

/// On a floor below everything (3D) or just outside the drawn grid (top view).
AxesPlacement place_axes(const GridDrawing& d, double az, int px) {
  AxesPlacement a;
  a.label_px = static_cast<int>(std::lround(0.85 * px));
  a.left_is_u0 = d.height ? std::cos(az) >= 0.0 : true;
  a.side = a.left_is_u0 ? -1.0 : 1.0;
  a.tick = 0.025 * d.extent;
  a.v_axis = d.v0;
  a.u_axis = a.left_is_u0 ? d.u0 : d.u1;
  a.z_axis = d.eps;
  if (d.height) {
    a.z_axis = std::min(0.0, units::mm_from_um(d.g.deviation.minCoeff()) * d.mag) - 0.05 * d.extent;
  } else {
    for (Eigen::Index j = 0; j < d.cols; ++j) a.v_axis = std::min(a.v_axis, d.actual(0, j).y());
    a.v_axis -= 0.03 * d.extent;
    a.u_axis += a.side * 0.03 * d.extent;
  }
  return a;
}

/// The u and v axes with ticks, tick labels and titles parallel to them; sets a.v_label_w.
void add_axes(detail::Scene3D& scene, const GridDrawing& d, AxesPlacement& a, int px) {
  const double v_axis = a.v_axis, u_axis = a.u_axis, z_axis = a.z_axis, tick = a.tick, side = a.side;
  std::vector<detail::Polyline> axis_lines{{{d.u0, v_axis, z_axis}, {d.u1, v_axis, z_axis}},
                                           {{u_axis, d.v0, z_axis}, {u_axis, d.v1, z_axis}}};
  const int u_dec = detail::decimals_for_step(detail::nice_step(d.u1 - d.u0, 5));
  for (double u : detail::nice_ticks({d.u0, d.u1}, 5)) {
    axis_lines.push_back({{u, v_axis, z_axis}, {u, v_axis - tick, z_axis}});
    detail::OverlayText t;
    t.y = -0.3F * static_cast<float>(px);
    t.text = detail::format_value(u, u_dec);
    t.px = a.label_px;
    t.h = HAlign::centre;
    t.v = detail::VAlign::top;
    scene.add_label({u, v_axis - tick, z_axis}, t);
  }
  const int v_dec = detail::decimals_for_step(detail::nice_step(d.v1 - d.v0, 5));
  for (double v : detail::nice_ticks({d.v0, d.v1}, 5)) {
    axis_lines.push_back({{u_axis, v, z_axis}, {u_axis + side * tick, v, z_axis}});
    detail::OverlayText t;
    t.x = -0.3F * static_cast<float>(px);
    t.text = detail::format_value(v, v_dec);
    t.px = a.label_px;
    t.h = HAlign::right;
    t.v = detail::VAlign::centre;
    a.v_label_w = std::max(a.v_label_w, detail::text_width_estimate(t.text, a.label_px));
    scene.add_label({u_axis + side * tick, v, z_axis}, t);
  }
  scene.add_lines(axis_lines, colours::text, 1.2);
  // Titles parallel to their axes, beyond the tick labels.
  const Eigen::Vector3d centre(0.5 * (d.u0 + d.u1), 0.5 * (d.v0 + d.v1), z_axis);
  detail::OverlayText t;
  t.px = px;
  t.text = detail::axis_label(d.g.u_axis.title, d.g.u_axis.unit);
  const Eigen::Vector3d ua(d.u0, v_axis - tick, z_axis), ub(d.u1, v_axis - tick, z_axis);
  scene.add_axis_title(ua, ub, centre, t, static_cast<float>(0.3 * px + 1.3 * a.label_px + 0.4 * px));
  t.text = detail::axis_label(d.g.v_axis.title, d.g.v_axis.unit);
  const Eigen::Vector3d va(u_axis + side * tick, d.v0, z_axis), vb(u_axis + side * tick, d.v1, z_axis);
  scene.add_axis_title(va, vb, centre, t, static_cast<float>(0.3 * px + a.v_label_w + 0.5 * px));
}

/// A vertical scale beside the front corner on the floor (3D): `shown_um` at the magnification, labelled.
void add_height_scale(detail::Scene3D& scene, const GridDrawing& d, const AxesPlacement& a, double shown_um,
                      const std::string& label, int px) {
  const Eigen::Vector3d base(a.left_is_u0 ? d.u1 + 0.05 * d.extent : d.u0 - 0.05 * d.extent, a.v_axis, a.z_axis);
  const Eigen::Vector3d top = base + Eigen::Vector3d(0.0, 0.0, units::mm_from_um(shown_um) * d.mag);
  scene.add_lines({{base, top}, {top - Eigen::Vector3d(0.5 * a.tick, 0, 0), top + Eigen::Vector3d(0.5 * a.tick, 0, 0)}},
                  colours::actual, 2.0);
  detail::OverlayText t;
  t.x = (a.left_is_u0 ? 0.4F : -0.4F) * static_cast<float>(px);
  t.text = label;
  t.px = a.label_px;
  t.colour = colours::actual;
  t.h = a.left_is_u0 ? HAlign::left : HAlign::right;
  t.v = detail::VAlign::centre;
  scene.add_label(top, t);
}

} // namespace

RenderResult render_grid_topology(const GridTopology& g, const std::filesystem::path& png) {
  const GridDrawing d(g, grid_magnification(g));
  const Range colour = colour_range(g.deviation.minCoeff(), g.deviation.maxCoeff(), g.scale);
  const int px = detail::font_px(g.size, g.font_px);

  detail::Scene3D scene(g.size, px);
  // View: in 3D from the v_min side, turned by the azimuth about the deviation axis and raised by the elevation.
  const double az = g.azimuth_deg * std::numbers::pi / 180.0;
  const double el = g.elevation_deg * std::numbers::pi / 180.0;
  const Eigen::Vector3d direction =
      d.height ? Eigen::Vector3d(-std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), -std::sin(el))
               : Eigen::Vector3d(0.0, 0.0, -1.0);
  const Eigen::Vector3d up = d.height ? Eigen::Vector3d(0.0, 0.0, 1.0) : Eigen::Vector3d(0.0, 1.0, 0.0);
  scene.set_auto_camera(direction, up, true, 1.12);

  if (g.fill) add_surface(scene, d, colour, direction);
  scene.add_lines(d.lines(false), colours::nominal, std::max(1.2, 0.08 * px));
  scene.add_lines(d.lines(true), colours::actual, std::max(2.0, 0.13 * px));
  add_nodes(scene, d, colour, px);

  // The scale bar's length: from the data, or from a fixed colour range (panels that share a scale then share the
  // bar too, and a near-zero "after" state does not get a 0.0 µm bar).
  const double data_max = g.deviation.cwiseAbs().maxCoeff();
  const double max_dev = g.scale.mode == RangeMode::fixed
                             ? std::max({data_max, std::abs(g.scale.fixed.min), std::abs(g.scale.fixed.max)})
                             : std::max(data_max, g.scale.resolution);
  const double shown = max_dev > 0.0 ? nice_floor(max_dev) : 1.0; // µm, for the scale and the caption
  const int shown_decimals = detail::decimals_for_step(shown);     // 0.01 µm reads "0.01", not "0.0"
  AxesPlacement axes = place_axes(d, az, px);
  add_axes(scene, d, axes, px);
  // The height scale's label sticks out of the fitted scene on its side (right of the front corner when u0 is on the
  // left): room for it, or the colour bar covers "0.01 µm" (issue 15 review).
  const std::string scale_label = detail::format_value(shown, shown_decimals) + " µm";
  const double scale_label_room = d.height ? detail::text_width_estimate(scale_label, axes.label_px) + 0.4 * px : 0.0;
  scene.set_insets(static_cast<float>(axes.v_label_w + 2.4 * px + (axes.left_is_u0 ? 0.0 : scale_label_room)),
                   static_cast<float>(2.6 * px), static_cast<float>(axes.left_is_u0 ? scale_label_room : 0.0));
  if (d.height) add_height_scale(scene, d, axes, shown, scale_label, px);

  const double drawn_mm = units::mm_from_um(shown) * d.mag;
  scene.set_title(g.title);
  scene.set_caption(fmt::format("nominal grid black, actual blue; deviation {} ×{} ({} µm drawn as {} mm)",
                                d.height ? "(height)" : "(along v)", detail::format_value(d.mag, d.mag < 10 ? 1 : 0),
                                detail::format_value(shown, shown_decimals),
                                detail::format_value(drawn_mm, drawn_mm < 10 ? 1 : 0)));
  scene.set_colour_bar(colour, detail::axis_label(g.scale.title, g.scale.unit));
  scene.render(png);
  return {colour, std::nullopt, std::nullopt};
}

} // namespace geartopo::render
