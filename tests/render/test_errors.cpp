// Clear exceptions, not crashes: no data, inconsistent input, unwritable output.

#include "geartopo/render/charts.hpp"
#include "geartopo/render/composite.hpp"
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

/// Runs `f`, expects an exception of type E whose message contains `text`.
template <typename E, typename F>
void expect_error(F f, const std::string& text) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one mentioning '" << text << "'";
  } catch (const E& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

const std::filesystem::path nowhere = "/nonexistent-directory/figure.png";

TEST(RenderErrors, NoDataPointsGiveAClearException) {
  const auto png = test::output("never_written.png");
  LineChart line;
  line.series = {{"empty", {}, {}, {}, 2.0, Marker::none, 7.0, false}};
  expect_error<std::invalid_argument>([&] { render_line_chart(line, png); }, "no data point");
  line.series[0].x = {std::nan("")};
  line.series[0].y = {1.0};
  expect_error<std::invalid_argument>([&] { render_line_chart(line, png); }, "no data point");
  expect_error<std::invalid_argument>([&] { render_line_chart(LineChart{}, png); }, "no data point");

  expect_error<std::invalid_argument>([&] { render_bar_chart(BarChart{}, png); }, "no bar series");
  BarChart bars;
  bars.bars = {{"empty", {}, {}}};
  expect_error<std::invalid_argument>([&] { render_bar_chart(bars, png); }, "no data point");

  expect_error<std::invalid_argument>([&] { render_heat_map(HeatMap{}, png); }, "no data point");
  HeatMap nan_map;
  nan_map.values = Eigen::MatrixXd::Constant(2, 2, std::numeric_limits<double>::quiet_NaN());
  expect_error<std::invalid_argument>([&] { render_heat_map(nan_map, png); }, "no data point");

  expect_error<std::invalid_argument>([&] { render_grid_topology(GridTopology{}, png); }, "no data point");
  expect_error<std::invalid_argument>([&] { render_surface_view(SurfaceView{}, png); }, "no data point");
  expect_error<std::invalid_argument>([&] { render_composite(Composite{}, png); }, "no panel");
  EXPECT_FALSE(std::filesystem::exists(png));
}

TEST(RenderErrors, InconsistentInputIsRejected) {
  const auto png = test::output("never_written.png");
  LineChart line;
  line.series = {{"s", {1.0, 2.0}, {1.0}, {}, 2.0, Marker::none, 7.0, false}};
  expect_error<std::invalid_argument>([&] { render_line_chart(line, png); }, "2 x values but 1 y values");

  GridTopology grid;
  grid.u = Eigen::MatrixXd::Zero(3, 3);
  grid.v = Eigen::MatrixXd::Zero(3, 4);
  grid.deviation = Eigen::MatrixXd::Zero(3, 3);
  expect_error<std::invalid_argument>([&] { render_grid_topology(grid, png); }, "same size");

  SurfaceView view;
  SurfaceMesh mesh;
  mesh.vertices = Eigen::Matrix3Xd::Zero(3, 3);
  mesh.faces.resize(3, 1);
  mesh.faces << 0, 1, 3;
  view.meshes = {mesh};
  expect_error<std::invalid_argument>([&] { render_surface_view(view, png); }, "face index");

  HeatMap map;
  map.values = Eigen::MatrixXd::Zero(2, 3);
  map.x_centres = {1.0, 2.0};
  expect_error<std::invalid_argument>([&] { render_heat_map(map, png); }, "2 x centres for 3 cells");

  LineChart tiny;
  tiny.series = {{"s", {0.0, 1.0}, {0.0, 1.0}, {}, 2.0, Marker::none, 7.0, false}};
  tiny.size = {4, 4};
  expect_error<std::invalid_argument>([&] { render_line_chart(tiny, png); }, "out of range");
}

TEST(RenderErrors, UnwritableOutputIsARuntimeError) {
  LineChart line;
  line.series = {{"s", {0.0, 1.0}, {0.0, 1.0}, {}, 2.0, Marker::none, 7.0, false}};
  line.size = {300, 200};
  expect_error<std::runtime_error>([&] { render_line_chart(line, nowhere); }, "/nonexistent-directory/figure.png: cannot write: its folder does not exist");
  Image img;
  img.width = img.height = 2;
  img.pixels.assign(4, colours::white);
  expect_error<std::runtime_error>([&] { write_png(img, nowhere); }, "cannot write");
  expect_error<std::runtime_error>([&] { read_png(nowhere); }, "no PNG file");
  Composite c;
  c.panels = {{nowhere, ""}};
  expect_error<std::runtime_error>([&] { render_composite(c, test::output("never.png")); }, "no PNG file");
}

} // namespace
} // namespace geartopo::render
