// Colour-mapped figures (grid topology, heat map, surface): the colour scale spans the data and both ends' colours
// are in the image.

#include "geartopo/render/colour_map.hpp"
#include "geartopo/render/grid_view.hpp"
#include "geartopo/render/heat_map.hpp"
#include "geartopo/render/image.hpp"
#include "geartopo/render/surface_view.hpp"
#include "render_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace geartopo::render {
namespace {

/// rows × cols deviations from −7 µm (node 0, 0) to +12 µm (last node), smooth in between.
Eigen::MatrixXd deviations(int rows, int cols) {
  Eigen::MatrixXd d(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const double s = (static_cast<double>(i) / (rows - 1) + static_cast<double>(j) / (cols - 1)) / 2.0;
      d(i, j) = -7.0 + 19.0 * s * s + 0.8 * std::sin(3.0 * i + j) * s * (1.0 - s);
    }
  d(0, 0) = -7.0;
  d(rows - 1, cols - 1) = 12.0;
  return d;
}

GridTopology topology(GridOffset offset) {
  GridTopology g;
  g.title = "Flank topology, left flank";
  const int rows = 7, cols = 9;
  g.u.resize(rows, cols);
  g.v.resize(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      g.u(i, j) = 2.0 + 3.5 * j; // axial position, mm
      g.v(i, j) = 4.0 + 2.5 * i; // roll length, mm
    }
  g.deviation = deviations(rows, cols);
  g.offset = offset;
  g.size = {1000, 700};
  return g;
}

TEST(GridTopology, DataRangeScaleAndBothEndColoursAppear) {
  GridTopology g = topology(GridOffset::height);
  g.scale.mode = RangeMode::data;
  const auto png = test::output("grid_topology_3d.png");
  const RenderResult r = render_grid_topology(g, png);
  test::expect_figure(png, g.size);
  ASSERT_TRUE(r.colour_range);
  EXPECT_EQ(*r.colour_range, (Range{-7.0, 12.0}));
  const Image img = read_png(png);
  EXPECT_TRUE(contains_colour(img, colour_for(-7.0, *r.colour_range), 6, 30)) << "most negative node";
  EXPECT_TRUE(contains_colour(img, colour_for(12.0, *r.colour_range), 6, 30)) << "most positive node";
  EXPECT_TRUE(contains_colour(img, colours::actual, 30, 300)) << "actual grid lines";
}

TEST(GridTopology, DefaultScaleIsSymmetricAndTheBarShowsIt) {
  GridTopology g = topology(GridOffset::in_plane);
  const auto png = test::output("grid_topology_in_plane.png");
  const RenderResult r = render_grid_topology(g, png);
  test::expect_figure(png, g.size);
  EXPECT_EQ(*r.colour_range, (Range{-12.0, 12.0}));
  const Image img = read_png(png);
  // −12 µm occurs in no node: its colour comes from the colour bar alone.
  EXPECT_TRUE(contains_colour(img, colour_for(-12.0, *r.colour_range), 6, 20)) << "colour bar, negative end";
  EXPECT_TRUE(contains_colour(img, colour_for(-7.0, *r.colour_range), 6, 30)) << "most negative node";
  EXPECT_TRUE(contains_colour(img, colour_for(12.0, *r.colour_range), 6, 30)) << "most positive node";
}

TEST(GridTopology, MagnificationAutomaticOrGiven) {
  GridTopology g = topology(GridOffset::height);
  const double automatic = grid_magnification(g);
  const double mantissa = automatic / std::pow(10.0, std::floor(std::log10(automatic)));
  EXPECT_TRUE(std::abs(mantissa - 1.0) < 1e-9 || std::abs(mantissa - 2.0) < 1e-9 || std::abs(mantissa - 5.0) < 1e-9)
      << automatic;
  // 12 µm shown as at most 15 % of the 28 mm grid.
  EXPECT_LE(12.0e-3 * automatic, 0.15 * 28.0 + 1e-9);
  EXPECT_GT(12.0e-3 * automatic, 0.15 * 28.0 / 2.5);
  g.magnification = 750.0;
  EXPECT_DOUBLE_EQ(grid_magnification(g), 750.0);
  // Rounding noise (an ideal machine's 1e-9 µm) is magnified as if it were the resolution, 0.01 µm: 0.01 µm shown
  // as at most 15 % of the grid, not 1e-9 µm.
  g.magnification = 0.0;
  g.deviation *= 1e-9 / 12.0;
  const double noise = grid_magnification(g);
  EXPECT_LE(0.01e-3 * noise, 0.15 * 28.0 + 1e-9);
  EXPECT_GT(0.01e-3 * noise, 0.15 * 28.0 / 2.5);
}

HeatMap residual_map() {
  HeatMap h;
  h.title = "Residual map";
  h.x = {"face width", "mm", {}, {}};
  h.y = {"roll length", "mm", {}, {}};
  h.values = deviations(6, 8);
  for (int j = 0; j < 8; ++j) h.x_centres.push_back(2.0 + 4.0 * j);
  for (int i = 0; i < 6; ++i) h.y_centres.push_back(4.0 + 3.0 * i);
  h.size = {1000, 650};
  return h;
}

TEST(HeatMap, DataRangeScaleAndBothEndCellsInTheirColours) {
  HeatMap h = residual_map();
  h.scale.mode = RangeMode::data;
  h.show_values = false;
  const auto png = test::output("heat_map_data_range.png");
  const RenderResult r = render_heat_map(h, png);
  test::expect_figure(png, h.size);
  EXPECT_EQ(*r.colour_range, (Range{-7.0, 12.0}));
  const Image img = read_png(png);
  // A cell is ~100 × 80 px: far more pixels than the colour bar's ends.
  EXPECT_GT(count_colour(img, colour_for(-7.0, *r.colour_range)), 3000U) << "most negative cell";
  EXPECT_GT(count_colour(img, colour_for(12.0, *r.colour_range)), 3000U) << "most positive cell";
  EXPECT_EQ(*r.x_range, (Range{0.0, 32.0})); // cell edges
  EXPECT_EQ(*r.y_range, (Range{2.5, 20.5}));
}

TEST(HeatMap, GivenSymmetricRangeValuesAndMarkedCells) {
  HeatMap h = residual_map();
  h.scale.mode = RangeMode::fixed;
  h.scale.fixed = {-15.0, 15.0};
  h.values(2, 3) = std::numeric_limits<double>::quiet_NaN(); // no data: grey
  const auto plain = test::output("heat_map_plain.png");
  EXPECT_EQ(*render_heat_map(h, plain).colour_range, (Range{-15.0, 15.0}));
  h.marked = h.values.array() > 8.0;
  h.marked_label = "outside tolerance";
  const auto marked = test::output("heat_map_marked.png");
  render_heat_map(h, marked);
  test::expect_figure(marked, h.size);
  const Image a = read_png(plain);
  const Image b = read_png(marked);
  EXPECT_TRUE(contains_colour(a, colours::light_grey, 3, 1000)) << "NaN cell";
  EXPECT_GT(count_colour(b, colours::black, 40), count_colour(a, colours::black, 40) + 500) << "outline and hatching";
}

/// A flat plate in the x-y plane, 60 × 20 mm: left half −7 µm, right half +12 µm (4 × 2 vertices).
SurfaceMesh plate() {
  SurfaceMesh m;
  m.vertices.resize(3, 8);
  m.values.resize(8);
  const double xs[4] = {0.0, 30.0, 30.001, 60.0};
  const double vs[4] = {-7.0, -7.0, 12.0, 12.0};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 4; ++j) {
      m.vertices.col(i * 4 + j) = Eigen::Vector3d(xs[j], 20.0 * i, 0.0);
      m.values(i * 4 + j) = vs[j];
    }
  m.faces.resize(3, 6);
  for (int j = 0; j < 3; ++j) {
    m.faces.col(2 * j) = Eigen::Vector3i(j, j + 1, j + 5);
    m.faces.col(2 * j + 1) = Eigen::Vector3i(j, j + 5, j + 4);
  }
  return m;
}

TEST(SurfaceView, PlateSeenSquareOnKeepsTheMapColours) {
  SurfaceView v;
  v.title = "Flank deviation";
  v.meshes = {plate()};
  v.view_direction = {0.0, 0.0, -1.0};
  v.view_up = {0.0, 1.0, 0.0};
  v.scale.mode = RangeMode::data;
  v.size = {900, 500};
  const auto png = test::output("surface_plate.png");
  const RenderResult r = render_surface_view(v, png);
  test::expect_figure(png, v.size);
  EXPECT_EQ(*r.colour_range, (Range{-7.0, 12.0}));
  const Image img = read_png(png);
  EXPECT_GT(count_colour(img, colour_for(-7.0, *r.colour_range)), 5000U) << "negative half";
  EXPECT_GT(count_colour(img, colour_for(12.0, *r.colour_range)), 5000U) << "positive half";
}

TEST(SurfaceView, SeveralMeshesAndAnExplicitCamera) {
  SurfaceMesh body = plate();
  body.values.resize(0); // grey, no values
  for (Eigen::Index k = 0; k < body.vertices.cols(); ++k) body.vertices.col(k) += Eigen::Vector3d(-10.0, 25.0, -5.0);
  SurfaceMesh flank = plate();
  flank.edges = true;
  SurfaceView v;
  v.title = "Gear and flank";
  v.caption = "oblique view";
  v.meshes = {body, flank};
  Camera cam;
  cam.position = {30.0, -60.0, 80.0};
  cam.focal_point = {25.0, 20.0, 0.0};
  cam.view_up = {0.0, 0.0, 1.0};
  cam.parallel = false;
  v.camera = cam;
  v.size = {800, 600};
  const auto png = test::output("surface_two_meshes.png");
  const RenderResult r = render_surface_view(v, png);
  test::expect_figure(png, v.size);
  EXPECT_EQ(*r.colour_range, (Range{-12.0, 12.0}));

  SurfaceView grey;
  grey.meshes = {body};
  grey.size = {400, 300};
  const auto png2 = test::output("surface_grey.png");
  EXPECT_FALSE(render_surface_view(grey, png2).colour_range) << "no values, no colour scale";
  test::expect_figure(png2, grey.size, 20.0);
}

} // namespace
} // namespace geartopo::render
