// A 3D view on an off-screen context: layer 0 holds a white background renderer and the 3D renderer (viewport
// between the title, the caption and the colour bar); layer 1 holds a vtkContextActor with the 2D overlay.

#include "detail/scene3d.hpp"
#include "detail/layout.hpp"
#include "detail/offscreen.hpp"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkContextActor.h>
#include <vtkContextItem.h>
#include <vtkContextScene.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>

namespace geartopo::render::detail {

namespace {

vtkSmartPointer<vtkUnsignedCharArray> colour_array(const std::vector<Rgb>& colours) {
  auto array = vtkSmartPointer<vtkUnsignedCharArray>::New();
  array->SetName("colours");
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(static_cast<vtkIdType>(colours.size()));
  for (std::size_t i = 0; i < colours.size(); ++i) {
    const unsigned char c[3] = {colours[i].r, colours[i].g, colours[i].b};
    array->SetTypedTuple(static_cast<vtkIdType>(i), c);
  }
  return array;
}

void set_colour(vtkProperty* p, Rgb c) {
  p->SetColor(c.r / 255.0, c.g / 255.0, c.b / 255.0);
}

struct Label {
  Eigen::Vector3d anchor;
  OverlayText text;
};

struct AxisTitle {
  Eigen::Vector3d a, b, away_from;
  OverlayText text;
  float offset = 0.0F;
};

struct AutoCamera {
  Eigen::Vector3d direction;
  Eigen::Vector3d up;
  bool parallel = true;
  double margin = 1.05;
};

} // namespace

struct Scene3D::Impl {
  ImageSize size;
  int px;
  Offscreen offscreen; // before every VTK object: the context outlives them
  vtkNew<vtkRenderer> background;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderer> overlay_renderer;
  std::vector<Eigen::Vector3d> fit_points; // everything the automatic camera must show
  std::vector<Label> labels;
  std::vector<AxisTitle> axis_titles;
  std::string title;
  std::string caption;
  std::optional<Range> bar_range;
  std::string bar_label;
  std::optional<AutoCamera> auto_camera;
  std::optional<Camera> camera;
  float inset_left = 0.0F;
  float inset_bottom = 0.0F;
  float inset_right = 0.0F;

  Impl(ImageSize s, int font_px) : size(s), px(font_px), offscreen(s.width, s.height) {
    vtkGenericOpenGLRenderWindow* window = offscreen.window();
    window->SetNumberOfLayers(2);
    background->SetBackground(1.0, 1.0, 1.0);
    background->SetLayer(0);
    background->InteractiveOff();
    renderer->SetBackground(1.0, 1.0, 1.0);
    renderer->SetLayer(0);
    overlay_renderer->SetLayer(1);
    overlay_renderer->PreserveColorBufferOn();
    overlay_renderer->InteractiveOff();
    window->AddRenderer(background);
    window->AddRenderer(renderer);
    window->AddRenderer(overlay_renderer);
  }

  void add_actor(vtkPolyData* data, bool direct_colours, const std::function<void(vtkActor*)>& style) {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(data);
    if (direct_colours) {
      mapper->ScalarVisibilityOn();
      mapper->SetScalarModeToUsePointData();
      mapper->SetColorModeToDirectScalars();
    } else {
      mapper->ScalarVisibilityOff();
    }
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    style(actor);
    renderer->AddActor(actor);
  }

  /// Viewport of the 3D renderer in pixels: x0, y0, x1, y1.
  std::array<double, 4> viewport_px() const {
    const double top = title.empty() ? 0.6 * px : 2.8 * px;
    const double bottom = caption.empty() ? 0.6 * px : 2.3 * px;
    const double right = bar_range ? colour_bar_reserve(*bar_range, bar_label, px) : 0.6 * px;
    return {0.6 * px + inset_left, bottom + inset_bottom, size.width - right - inset_right, size.height - top};
  }

  void place_camera() {
    vtkCamera* cam = renderer->GetActiveCamera();
    const auto vp = viewport_px();
    const double aspect = (vp[2] - vp[0]) / std::max(vp[3] - vp[1], 1.0);
    Eigen::Vector3d d;
    Eigen::Vector3d up;
    bool parallel = true;
    double margin = 1.05;
    std::optional<Eigen::Vector3d> focal;
    if (camera) {
      d = camera->focal_point - camera->position;
      up = camera->view_up;
      parallel = camera->parallel;
      focal = camera->focal_point;
    } else {
      const AutoCamera a = auto_camera.value_or(AutoCamera{{-1, -1, -1}, {0, 0, 1}, true, 1.05});
      d = a.direction;
      up = a.up;
      parallel = a.parallel;
      margin = a.margin;
    }
    if (!(d.norm() > 0.0)) d = Eigen::Vector3d(0, 0, -1);
    d.normalize();
    up -= up.dot(d) * d;
    if (up.norm() < 1e-9) up = std::abs(d.z()) < 0.9 ? Eigen::Vector3d(0, 0, 1) : Eigen::Vector3d(0, 1, 0);
    up -= up.dot(d) * d;
    up.normalize();
    const Eigen::Vector3d right = d.cross(up);
    // Extents of the scene across and along the view.
    double r0 = std::numeric_limits<double>::infinity(), r1 = -r0, u0 = r0, u1 = -r0, d0 = r0, d1 = -r0;
    for (const Eigen::Vector3d& p : fit_points) {
      r0 = std::min(r0, p.dot(right));
      r1 = std::max(r1, p.dot(right));
      u0 = std::min(u0, p.dot(up));
      u1 = std::max(u1, p.dot(up));
      d0 = std::min(d0, p.dot(d));
      d1 = std::max(d1, p.dot(d));
    }
    if (fit_points.empty()) r0 = r1 = u0 = u1 = d0 = d1 = 0.0;
    const double half_h = std::max({0.5 * (u1 - u0), 0.5 * (r1 - r0) / aspect, 1e-6}) * margin;
    const double depth = std::max(d1 - d0, 1e-6);
    Eigen::Vector3d f = focal.value_or(right * 0.5 * (r0 + r1) + up * 0.5 * (u0 + u1) + d * 0.5 * (d0 + d1));
    const double view_angle = camera ? camera->view_angle_deg : 30.0;
    double distance = 0.0;
    if (camera) {
      distance = (camera->focal_point - camera->position).norm();
    } else {
      distance = parallel ? 2.0 * depth + half_h
                          : half_h / std::tan(0.5 * view_angle * std::numbers::pi / 180.0) + 0.5 * depth;
    }
    const Eigen::Vector3d position = camera ? camera->position : Eigen::Vector3d(f - d * distance);
    cam->SetFocalPoint(f.x(), f.y(), f.z());
    cam->SetPosition(position.x(), position.y(), position.z());
    cam->SetViewUp(up.x(), up.y(), up.z());
    cam->SetParallelProjection(parallel);
    cam->SetViewAngle(view_angle);
    cam->SetParallelScale(camera && camera->parallel_scale > 0.0 ? camera->parallel_scale : half_h);
    renderer->ResetCameraClippingRange();
  }
};

Scene3D::Scene3D(ImageSize size, int px) : impl_(std::make_unique<Impl>(size, px)) {}
Scene3D::~Scene3D() = default;

void Scene3D::add_lines(const std::vector<Polyline>& lines, Rgb colour, double width_px) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> cells;
  for (const Polyline& line : lines) {
    if (line.size() < 2) continue;
    cells->InsertNextCell(static_cast<vtkIdType>(line.size()));
    for (const Eigen::Vector3d& p : line) {
      cells->InsertCellPoint(points->InsertNextPoint(p.data()));
      impl_->fit_points.push_back(p);
    }
  }
  vtkNew<vtkPolyData> data;
  data->SetPoints(points);
  data->SetLines(cells);
  impl_->add_actor(data, false, [&](vtkActor* actor) {
    set_colour(actor->GetProperty(), colour);
    actor->GetProperty()->LightingOff();
    actor->GetProperty()->SetLineWidth(static_cast<float>(width_px));
  });
}

void Scene3D::add_points(const std::vector<Eigen::Vector3d>& pts, const std::vector<Rgb>& colours, double size_px) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> cells;
  for (const Eigen::Vector3d& p : pts) {
    cells->InsertNextCell(1);
    cells->InsertCellPoint(points->InsertNextPoint(p.data()));
    impl_->fit_points.push_back(p);
  }
  vtkNew<vtkPolyData> data;
  data->SetPoints(points);
  data->SetVerts(cells);
  data->GetPointData()->SetScalars(colour_array(colours));
  impl_->add_actor(data, true, [&](vtkActor* actor) {
    actor->GetProperty()->LightingOff();
    actor->GetProperty()->SetPointSize(static_cast<float>(size_px));
    actor->GetProperty()->RenderPointsAsSpheresOn();
  });
}

void Scene3D::add_mesh(const Eigen::Matrix3Xd& vertices, const Eigen::Matrix3Xi& faces,
                       const std::vector<Rgb>& vertex_colours, Rgb colour, double opacity, bool lit, bool edges) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(vertices.cols());
  for (Eigen::Index i = 0; i < vertices.cols(); ++i) {
    points->SetPoint(i, vertices(0, i), vertices(1, i), vertices(2, i));
    impl_->fit_points.emplace_back(vertices.col(i));
  }
  vtkNew<vtkCellArray> cells;
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    const vtkIdType ids[3] = {faces(0, f), faces(1, f), faces(2, f)};
    cells->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> data;
  data->SetPoints(points);
  data->SetPolys(cells);
  const bool coloured = !vertex_colours.empty();
  if (coloured) data->GetPointData()->SetScalars(colour_array(vertex_colours));
  vtkSmartPointer<vtkPolyData> input = data.GetPointer();
  if (lit) {
    vtkNew<vtkPolyDataNormals> normals;
    normals->SetInputData(data);
    normals->SetFeatureAngle(40.0);
    normals->SplittingOn();
    normals->ConsistencyOn();
    normals->Update();
    input = normals->GetOutput();
  }
  impl_->add_actor(input, coloured, [&](vtkActor* actor) {
    vtkProperty* p = actor->GetProperty();
    set_colour(p, colour);
    p->SetOpacity(opacity);
    if (lit) {
      p->SetAmbient(0.25);
      p->SetDiffuse(0.75);
      p->SetSpecular(0.0);
    } else {
      p->LightingOff();
    }
    if (edges) {
      p->EdgeVisibilityOn();
      p->SetEdgeColor(0.35, 0.35, 0.35);
      p->SetLineWidth(0.6F);
    }
  });
}

void Scene3D::add_label(const Eigen::Vector3d& anchor, const OverlayText& text) {
  impl_->labels.push_back({anchor, text});
}

void Scene3D::add_axis_title(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& away_from,
                             const OverlayText& text, float offset_px) {
  impl_->axis_titles.push_back({a, b, away_from, text, offset_px});
}

void Scene3D::set_insets(float left, float bottom, float right) {
  impl_->inset_left = left;
  impl_->inset_bottom = bottom;
  impl_->inset_right = right;
}
void Scene3D::set_title(const std::string& title) { impl_->title = title; }
void Scene3D::set_caption(const std::string& caption) { impl_->caption = caption; }
void Scene3D::set_colour_bar(Range range, const std::string& label) {
  impl_->bar_range = range;
  impl_->bar_label = label;
}
void Scene3D::set_auto_camera(const Eigen::Vector3d& direction, const Eigen::Vector3d& up, bool parallel,
                              double margin) {
  impl_->auto_camera = AutoCamera{direction, up, parallel, margin};
}
void Scene3D::set_camera(const Camera& camera) { impl_->camera = camera; }

void Scene3D::render(const std::filesystem::path& png) {
  Impl& im = *impl_;
  const double W = im.size.width;
  const double H = im.size.height;
  const auto vp = im.viewport_px();
  im.renderer->SetViewport(vp[0] / W, vp[1] / H, vp[2] / W, vp[3] / H);
  im.place_camera();

  const auto project = [&](const Eigen::Vector3d& p) {
    im.renderer->SetWorldPoint(p.x(), p.y(), p.z(), 1.0);
    im.renderer->WorldToDisplay();
    double display[3];
    im.renderer->GetDisplayPoint(display);
    return Eigen::Vector2d(display[0], display[1]);
  };
  Overlay overlay;
  for (const Label& l : im.labels) {
    const Eigen::Vector2d d = project(l.anchor);
    OverlayText t = l.text;
    t.x = static_cast<float>(d.x()) + l.text.x;
    t.y = static_cast<float>(d.y()) + l.text.y;
    overlay.texts.push_back(t);
  }
  for (const AxisTitle& a : im.axis_titles) {
    const Eigen::Vector2d pa = project(a.a);
    const Eigen::Vector2d pb = project(a.b);
    const Eigen::Vector2d mid = 0.5 * (pa + pb);
    Eigen::Vector2d dir = pb - pa;
    if (dir.norm() < 1e-6) dir = Eigen::Vector2d(1.0, 0.0);
    dir.normalize();
    if (dir.x() < -1e-6 || (std::abs(dir.x()) <= 1e-6 && dir.y() < 0.0)) dir = -dir; // upright text
    Eigen::Vector2d normal(-dir.y(), dir.x());
    if (normal.dot(mid - project(a.away_from)) < 0.0) normal = -normal;
    const Eigen::Vector2d at = mid + normal * (a.offset + 0.6 * a.text.px);
    OverlayText t = a.text;
    t.x = static_cast<float>(at.x());
    t.y = static_cast<float>(at.y());
    t.h = HAlign::centre;
    t.v = VAlign::centre;
    t.angle_deg = static_cast<float>(std::atan2(dir.y(), dir.x()) * 180.0 / std::numbers::pi);
    overlay.texts.push_back(t);
  }
  if (!im.title.empty()) {
    OverlayText t;
    t.x = static_cast<float>(0.5 * W);
    t.y = static_cast<float>(H - 1.4 * im.px);
    t.text = im.title;
    t.px = static_cast<int>(std::lround(1.2 * im.px));
    t.bold = true;
    t.h = HAlign::centre;
    t.v = VAlign::centre;
    overlay.texts.push_back(t);
  }
  if (!im.caption.empty()) {
    OverlayText t;
    t.text = im.caption;
    t.px = static_cast<int>(std::lround(0.9 * im.px));
    // Centred under the 3D view, but kept inside the image: a viewport narrowed on one side (insets) would push a
    // long caption over the edge.
    const double half_w = 0.5 * text_width_estimate(t.text, t.px), margin = 0.3 * im.px;
    const double centre = 0.5 * (vp[0] + vp[2]);
    t.x = static_cast<float>(half_w + margin > 0.5 * W ? 0.5 * W : std::clamp(centre, half_w + margin, W - half_w - margin));
    t.y = static_cast<float>(1.1 * im.px);
    t.h = HAlign::centre;
    t.v = VAlign::centre;
    overlay.texts.push_back(t);
  }
  if (im.bar_range)
    overlay.bar = place_colour_bar(*im.bar_range, im.bar_label, im.px, im.size, static_cast<float>(vp[1]),
                                   static_cast<float>(vp[3]));
  vtkNew<vtkContextActor> context;
  context->GetScene()->AddItem(vtkSmartPointer<vtkContextItem>::Take(new_overlay_item(std::move(overlay))));
  im.overlay_renderer->AddActor(context);
  im.offscreen.save_png(png);
}

} // namespace geartopo::render::detail
