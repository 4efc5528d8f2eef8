#pragma once
// 3D view of triangle meshes with a colour-mapped scalar per vertex → PNG (docs/rendering.md).

#include "geartopo/render/common.hpp"

#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace geartopo::render {

/// A triangle mesh: vertices (mm, 3 × V), faces (vertex indices, 3 × F) and optionally one value per vertex (µm,
/// size V) drawn with the diverging colour map; without values the mesh is drawn in `colour`.
struct SurfaceMesh {
  Eigen::Matrix3Xd vertices;
  Eigen::Matrix3Xi faces;
  Eigen::VectorXd values;
  Rgb colour = colours::light_grey;
  double opacity = 1.0;
  bool edges = false; ///< draw the triangle edges
};

/// Explicit camera. parallel_scale = 0 (parallel) fits the scene; view_angle_deg is used for perspective.
struct Camera {
  Eigen::Vector3d position{0.0, 0.0, 1.0};
  Eigen::Vector3d focal_point{0.0, 0.0, 0.0};
  Eigen::Vector3d view_up{0.0, 1.0, 0.0};
  bool parallel = true;
  double parallel_scale = 0.0;
  double view_angle_deg = 30.0;
};

/// A text label at a 3D point (mm), e.g. "tooth 1": drawn in bold on a white box just above the point's image.
struct SurfaceLabel {
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  std::string text;
};

struct SurfaceView {
  std::string title;
  std::string caption; ///< one line under the view, e.g. "left flanks, tooth 1"
  std::vector<SurfaceMesh> meshes;
  /// Automatic camera (when `camera` is unset): looking along `view_direction`, fitted to all meshes.
  Eigen::Vector3d view_direction{-1.0, -1.0, -1.0};
  Eigen::Vector3d view_up{0.0, 0.0, 1.0};
  bool parallel = true;
  std::optional<Camera> camera;
  std::vector<SurfaceLabel> labels; ///< drawn over the meshes (not hidden by them)
  ColourScale scale; ///< range over the values of all meshes
  ImageSize size;
  int font_px = 0;
};

/// Renders `view` to `png`; returns the colour range used (unset when no mesh has values).
/// Throws std::invalid_argument for no mesh, an empty mesh, a face index out of range, values of the wrong size or
/// non-finite values; std::runtime_error when rendering or writing fails.
RenderResult render_surface_view(const SurfaceView& view, const std::filesystem::path& png);

} // namespace geartopo::render
