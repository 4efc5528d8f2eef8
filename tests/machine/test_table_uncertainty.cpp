// geartopo tests — standard-uncertainty columns of error tables (`u_<component>_<unit>`) and the draw they give.
// Truth: the column values written in the files (docs/examples/x_axis_with_uncertainty.csv, tests/machine/data) and
// the documented draw value(p) + z·u(p) (docs/error-components.md, "Uncertainty columns").
// Units: file units (µm, µrad, mm, deg) in the fixtures; mm and rad in the library.
#include "test_helpers.hpp"

#include "geartopo/machine/error_table.hpp"
#include "geartopo/core/units.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace geartopo::machine {
namespace {

/// The documented example (docs/examples): X-axis table with u columns.
std::string example_table_path() {
  return std::string(GEARTOPO_MACHINE_TEST_DATA) + "/../../../docs/examples/x_axis_with_uncertainty.csv";
}

const ErrorSource& column_of(const std::vector<ErrorSource>& all, ComponentId id) {
  const auto it = std::find_if(all.begin(), all.end(), [&](const ErrorSource& s) { return s.id() == id; });
  if (it == all.end()) throw std::runtime_error("no column");
  return *it;
}

/// u_delta_xx_um of the example, as its comment states it: 0.5 µm + 1 µm/m·x, here in mm.
double example_u_delta_xx_mm(double x_mm) { return units::mm_from_um(0.5 + 0.001 * x_mm); }

TEST(TableUncertainty, TheExampleTableGivesEachColumnItsUncertainty) {
  const std::vector<ErrorSource> all = load_error_tables(example_table_path());
  ASSERT_EQ(all.size(), 3u); // u columns are not components of their own
  const ErrorSource& dxx = column_of(all, ComponentId::delta_xx);
  const ErrorSource& dyx = column_of(all, ComponentId::delta_yx);
  const ErrorSource& ezx = column_of(all, ComponentId::epsilon_zx);
  EXPECT_TRUE(dxx.has_uncertainty_column());
  EXPECT_FALSE(dyx.has_uncertainty_column());
  EXPECT_TRUE(ezx.has_uncertainty_column());
  // At the rows and between them (the column is a straight line, which the not-a-knot spline reproduces).
  for (const double x : {0.0, 100.0, 150.0, 450.0, 730.0, 900.0})
    EXPECT_NEAR(dxx.uncertainty(x), example_u_delta_xx_mm(x), 1e-12) << x; // 1e-12 mm = 1 fm: rounding
  EXPECT_NEAR(ezx.uncertainty(420.0), units::rad_from_urad(2.0), 1e-15);
  EXPECT_EQ(dyx.uncertainty(420.0), 0.0);
  // The values are those of the value columns, not shifted by their uncertainty.
  EXPECT_NEAR(dxx.value(300.0), units::mm_from_um(6.6), 1e-15);
  const TableOrigin* o = dxx.origin();
  ASSERT_NE(o, nullptr);
  EXPECT_EQ(o->column, 2);
  EXPECT_EQ(o->uncertainty_column, 3);
  EXPECT_EQ(o->uncertainty_field, "u_delta_xx_um");
  EXPECT_NE(dxx.describe().find("'u_delta_xx_um'"), std::string::npos) << dxx.describe();
}

// One z for every position (fully correlated along the axis): the drawn offset at two positions is in the ratio of
// the column's values there, and its slope is z times the column's slope.
TEST(TableUncertainty, TheDrawnOffsetFollowsTheColumn) {
  const std::vector<ErrorSource> all = load_error_tables(example_table_path());
  const ErrorSource& dxx = column_of(all, ComponentId::delta_xx);
  const double z = -1.7;
  const ErrorSource drawn = dxx.drawn(z, units::mm_from_um(50.0)); // the scene's constant is not used
  const auto offset = [&](double x) { return drawn.value(x) - dxx.value(x); };
  for (const double x : {0.0, 150.0, 450.0, 900.0})
    EXPECT_NEAR(offset(x), z * example_u_delta_xx_mm(x), 1e-12) << x;
  // u(150)/u(750) = 0.65/1.25 µm, as the column says.
  EXPECT_NEAR(offset(150.0) / offset(750.0), 0.65 / 1.25, 1e-9);
  EXPECT_NEAR(drawn.rate(450.0) - dxx.rate(450.0), z * units::mm_from_um(0.001), 1e-15); // mm/mm
  // The machine model reads the same draw (it evaluates the columns of one table with one knot search).
  const MachineModel model(Strokes::skmc_1200w(), {drawn});
  ErrorVector e;
  model.errors_at({450.0, 0.0, 0.0, 0.0, 0.0}, e);
  EXPECT_EQ(e(index(ComponentId::delta_xx)), drawn.value(450.0));
}

// The documented equivalence: a column holding the constant u0 draws what the scene's constant u0 draws
// (machine.uncertainty.components), with the same z.
TEST(TableUncertainty, AConstantColumnDrawsLikeTheSceneConstant) {
  const std::string values = "x_mm,epsilon_zx_urad\n0,-8\n300,-5.8\n600,0.9\n900,12\n";
  const std::string with_u = "x_mm,epsilon_zx_urad,u_epsilon_zx_urad\n0,-8,2\n300,-5.8,2\n600,0.9,2\n900,12,2\n";
  const ErrorSource plain = parse_error_tables(values, "plain.csv").front();
  const ErrorSource column = parse_error_tables(with_u, "with_u.csv").front();
  const double u0 = units::rad_from_urad(2.0);
  for (const double z : {-2.3, 0.4, 1.9}) {
    const ErrorSource a = plain.drawn(z, u0), b = column.drawn(z, 0.0);
    for (double x = 0.0; x <= 900.0; x += 37.5) {
      EXPECT_NEAR(a.value(x), b.value(x), 1e-18) << x; // rad: 1e-12 µrad, rounding
      EXPECT_NEAR(a.rate(x), b.rate(x), 1e-18) << x;
    }
  }
  // Without a column the draw is the scene's constant: value + u·z, nothing else (as before columns existed).
  const ErrorSource shifted = plain.shifted(u0 * 0.4), drawn = plain.drawn(0.4, u0);
  for (double x = 0.0; x <= 900.0; x += 75.0) EXPECT_EQ(shifted.value(x), drawn.value(x));
  const ErrorSource constant = ErrorSource::constant(ComponentId::S_xy, 25.0, "urad");
  EXPECT_EQ(constant.drawn(-1.1, u0).value(0.0), units::rad_from_urad(25.0) + u0 * -1.1);
}

TEST(TableUncertainty, AColumnOfAPeriodicCTableIsPeriodicAndMayStandFirst) {
  const ErrorSource s = load_error_table(test::data_path("c_axis_u.csv"), ComponentId::epsilon_zc);
  ASSERT_TRUE(s.has_uncertainty_column());
  EXPECT_EQ(s.origin()->column, 3);
  EXPECT_EQ(s.origin()->uncertainty_column, 2);
  EXPECT_NEAR(s.uncertainty(0.5 * std::numbers::pi), units::rad_from_urad(2.0), 1e-18);
  EXPECT_NEAR(s.uncertainty(std::numbers::pi), units::rad_from_urad(3.0), 1e-18);
  const double h = 1e-9;
  EXPECT_NEAR(s.uncertainty(-h), s.uncertainty(h), 1e-15); // continuous across 0/360
  EXPECT_NEAR(s.value(0.5 * std::numbers::pi), units::rad_from_urad(12.0), 1e-18);
}

// A standard uncertainty is never negative: where the spline through non-negative values would dip below zero, the
// column's u(p) is held at 0 and the draw adds nothing there.
TEST(TableUncertainty, TheInterpolatedUncertaintyIsNeverNegative) {
  const std::string text = "x_mm,delta_xx_um,u_delta_xx_um\n0,0,0\n200,0,0\n400,0,3\n600,0,0\n900,0,0\n";
  const ErrorSource s = parse_error_tables(text, "dip.csv").front();
  const CubicSpline raw({0.0, 200.0, 400.0, 600.0, 900.0}, {0.0, 0.0, 3e-3, 0.0, 0.0}, CubicSpline::Ends::NotAKnot);
  bool dips = false;
  const ErrorSource drawn = s.drawn(2.0, 0.0);
  for (double x = 0.0; x <= 900.0; x += 5.0) {
    dips = dips || raw.value(x) < -1e-9;
    EXPECT_GE(s.uncertainty(x), 0.0) << x;
    EXPECT_NEAR(s.uncertainty(x), std::max(raw.value(x), 0.0), 1e-15) << x;
    EXPECT_GE(drawn.value(x), 0.0) << x; // the values are 0: the offset is 2·u(p) ≥ 0
  }
  EXPECT_TRUE(dips) << "the fixture should make the plain spline undershoot";
}

} // namespace
} // namespace geartopo::machine
