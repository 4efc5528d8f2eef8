#pragma once
// Internal: a 3D view on an off-screen context, fed with plain C++ primitives, with a 2D overlay (title, caption,
// labels anchored at 3D points, colour bar). Used by the grid topology view and the surface view. No VTK headers.

#include "geartopo/render/common.hpp"
#include "detail/overlay.hpp"
#include "geartopo/render/surface_view.hpp"

#include <Eigen/Core>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace geartopo::render::detail {

using Polyline = std::vector<Eigen::Vector3d>;

class Scene3D {
public:
  Scene3D(ImageSize size, int px);
  ~Scene3D();
  Scene3D(const Scene3D&) = delete;
  Scene3D& operator=(const Scene3D&) = delete;

  /// Unlit polylines of one colour.
  void add_lines(const std::vector<Polyline>& lines, Rgb colour, double width_px);
  /// Unlit round markers, one colour each.
  void add_points(const std::vector<Eigen::Vector3d>& points, const std::vector<Rgb>& colours, double size_px);
  /// Triangles with per-vertex colours (size V, or empty for `colour`). `lit`: headlight shading (a face seen
  /// square-on keeps its colour exactly); else flat colours. Opacity < 1 is blended without depth sorting.
  void add_mesh(const Eigen::Matrix3Xd& vertices, const Eigen::Matrix3Xi& faces, const std::vector<Rgb>& vertex_colours,
                Rgb colour, double opacity, bool lit, bool edges);
  /// Text placed at the projection of `anchor`, moved by (text.x, text.y) px.
  void add_label(const Eigen::Vector3d& anchor, const OverlayText& text);
  /// Text parallel to the projected segment a–b (kept upright), centred `offset_px` beside the segment's middle on
  /// the side away from the projection of `away_from` (an axis title).
  void add_axis_title(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& away_from,
                      const OverlayText& text, float offset_px);
  /// Extra room (px) left of, below and right of the 3D viewport, for labels placed outside the fitted scene.
  void set_insets(float left, float bottom, float right = 0.0F);
  void set_title(const std::string& title);
  void set_caption(const std::string& caption);
  void set_colour_bar(Range range, const std::string& label);
  /// Automatic camera looking along `direction`, fitted to everything added, with `margin` (1 = tight) round it.
  void set_auto_camera(const Eigen::Vector3d& direction, const Eigen::Vector3d& up, bool parallel, double margin);
  void set_camera(const Camera& camera);

  /// Places the camera, projects the labels, renders and writes the PNG. Call once.
  void render(const std::filesystem::path& png);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace geartopo::render::detail
