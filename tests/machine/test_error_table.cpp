// geartopo tests — error tables, polynomial and constant sources: values, units and located messages.
// Units: file units (µm, µrad, mm, deg) in the fixtures; mm and rad in the library.
#include "test_helpers.hpp"

#include "geartopo/machine/error_table.hpp"
#include "geartopo/core/units.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace geartopo::machine {
namespace {

using test::data_path;

TEST(ErrorTable, ReadsEveryColumnInInternalUnitsAndInterpolatesThroughTheRows) {
  const std::vector<ErrorSource> all = load_error_tables(data_path("x_axis.csv"));
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].id(), ComponentId::delta_xx);
  EXPECT_EQ(all[1].id(), ComponentId::delta_yx);
  EXPECT_EQ(all[2].id(), ComponentId::epsilon_zx);
  EXPECT_NEAR(all[0].value(100.0), 1.8e-3, 1e-15); // µm → mm
  EXPECT_NEAR(all[1].value(600.0), 0.2e-3, 1e-15);
  EXPECT_NEAR(all[2].value(500.0), 7.4e-6, 1e-18); // µrad → rad
  EXPECT_NEAR(all[0].value(900.0), 11.0e-3, 1e-15);
  const TableOrigin* o = all[2].origin();
  ASSERT_NE(o, nullptr);
  EXPECT_EQ(o->header_line, 3);
  EXPECT_EQ(o->first_line, 4);
  EXPECT_EQ(o->last_line, 14); // the blank line 9 is skipped but counted
  EXPECT_EQ(o->column, 4);
  EXPECT_EQ(o->field, "epsilon_zx_urad");
}

TEST(ErrorTable, PicksTheExpectedColumn) {
  const ErrorSource s = load_error_table(data_path("x_axis.csv"), ComponentId::delta_yx);
  EXPECT_EQ(s.id(), ComponentId::delta_yx);
  EXPECT_NEAR(s.value(300.0), -1.0e-3, 1e-15);
  try {
    load_error_table(data_path("x_axis.csv"), ComponentId::epsilon_xx);
    FAIL() << "missing column accepted";
  } catch (const geartopo::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x_axis.csv:3:1:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("epsilon_xx_urad"), std::string::npos) << e.what();
  }
}

TEST(ErrorTable, PeriodicCTableIsSmoothAcrossZero) {
  const ErrorSource s = load_error_table(data_path("c_axis.csv"), ComponentId::epsilon_zc);
  EXPECT_NEAR(s.value(0.0), 10.0e-6, 1e-18);
  EXPECT_NEAR(s.value(90.0 * units::kRadPerDeg), 15.8e-6, 1e-18);
  EXPECT_NEAR(s.value(360.0 * units::kRadPerDeg), 10.0e-6, 1e-18);
  EXPECT_NEAR(s.value(-30.0 * units::kRadPerDeg), 9.6e-6, 1e-18); // −30° is 330°
  const double h = 1e-9;
  EXPECT_NEAR(s.value(-h), s.value(h), 1e-14);
  EXPECT_NEAR(s.rate(-h), s.rate(h), 1e-12);
  EXPECT_NEAR(s.spline()->second_derivative(-h), s.spline()->second_derivative(h), 1e-10);
}

TEST(ErrorTable, ATableInDegreesIsAFunctionOfAlphaInRadians) {
  const ErrorSource s = load_error_table(data_path("a_axis.csv"), ComponentId::epsilon_xa);
  EXPECT_NEAR(s.value(30.0 * units::kRadPerDeg), 6.0e-6, 1e-18);
  // Rate in rad/rad: the table's slope in µrad/deg times 1e-6·180/π.
  const double fd = (s.value(20.0 * units::kRadPerDeg + 1e-6) - s.value(20.0 * units::kRadPerDeg - 1e-6)) / 2e-6;
  EXPECT_NEAR(s.rate(20.0 * units::kRadPerDeg), fd, 1e-9 * std::abs(fd));
}

struct BadTable {
  const char* file;
  const char* where;  // "file:line:column:" expected at the start of what()
  const char* phrase; // part of the message
};

void PrintTo(const BadTable& b, std::ostream* os) { *os << b.file; } // readable test names in ctest

class BadTables : public testing::TestWithParam<BadTable> {};

TEST_P(BadTables, FailWithFileLineAndColumn) {
  const BadTable& b = GetParam();
  const std::string path = data_path(b.file);
  try {
    const std::vector<ErrorSource> sources = load_error_tables(path);
    // Coverage of the stroke is checked when the model is built.
    const MachineModel model(Strokes::skmc_1200w(), sources);
    FAIL() << b.file << " was accepted";
  } catch (const geartopo::InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(test::data_path(b.where), 0), 0u) << what; // starts with the located file name
    EXPECT_NE(what.find(b.phrase), std::string::npos) << what;
    EXPECT_EQ(e.file(), path);
  }
}

INSTANTIATE_TEST_SUITE_P(
    ErrorTable, BadTables,
    testing::Values(
        BadTable{"bad_not_increasing.csv", "bad_not_increasing.csv:5:1: x_mm:", "strictly increasing"},
        BadTable{"bad_nan.csv", "bad_nan.csv:3:5: delta_xx_um:", "'nan' is not a finite number"},
        BadTable{"bad_inf.csv", "bad_inf.csv:3:5: delta_xx_um:", "'-inf' is not a finite number"},
        BadTable{"bad_not_number.csv", "bad_not_number.csv:3:6: delta_xx_um:", "'2.5um' is not a number"},
        BadTable{"bad_unknown_unit.csv", "bad_unknown_unit.csv:2:6: delta_xx_inch:", "unknown unit 'inch'"},
        BadTable{"bad_unit_kind.csv", "bad_unit_kind.csv:1:6: epsilon_xx_um:", "is an angle (use urad)"},
        BadTable{"bad_position_unit.csv", "bad_position_unit.csv:1:1: x_deg:", "not a position unit of axis X"},
        BadTable{"bad_column_count.csv", "bad_column_count.csv:3:8:", "the row has 2 fields, the header has 3"},
        BadTable{"bad_one_row.csv", "bad_one_row.csv:3:1:", "at least 2"},
        BadTable{"bad_stroke.csv", "bad_stroke.csv:4:1: x_mm:", "the X stroke [0, 900] mm"},
        BadTable{"bad_c_not_closed.csv", "bad_c_not_closed.csv:5:5: epsilon_zc_urad:", "repeat the 0 deg value"},
        BadTable{"bad_c_range.csv", "bad_c_range.csv:5:1: c_deg:", "must end at 360 deg"},
        BadTable{"bad_axis_mismatch.csv", "bad_axis_mismatch.csv:1:6: delta_xx_um:", "function of the X position"},
        BadTable{"bad_unknown_component.csv", "bad_unknown_component.csv:1:6: delta_qx_um:", "unknown error component"},
        BadTable{"bad_position_independent.csv", "bad_position_independent.csv:1:6: S_xy_urad:",
                 "position independent"},
        BadTable{"bad_empty.csv", "bad_empty.csv:", "no header line"},
        // Standard-uncertainty columns (u_<component>_<unit>): the same checks, plus their own.
        BadTable{"bad_u_without_component.csv", "bad_u_without_component.csv:1:18: u_delta_yx_um:",
                 "the file has no delta_yx column"},
        BadTable{"bad_u_negative.csv", "bad_u_negative.csv:3:9: u_delta_xx_um:", "'-0.1' is negative"},
        BadTable{"bad_u_nan.csv", "bad_u_nan.csv:3:9: u_delta_xx_um:", "'nan' is not a finite number"},
        BadTable{"bad_u_unit_kind.csv", "bad_u_unit_kind.csv:1:18: u_delta_xx_urad:", "is a length (use um)"},
        BadTable{"bad_u_unknown_component.csv", "bad_u_unknown_component.csv:1:18: u_delta_qx_um:",
                 "unknown error component 'delta_qx'"},
        BadTable{"bad_u_beyond.csv", "bad_u_beyond.csv:3:9: u_delta_xx_um:", "beyond ±1 mm"},
        BadTable{"bad_u_twice.csv", "bad_u_twice.csv:1:32: u_delta_xx_nm:", "second uncertainty column for delta_xx"},
        BadTable{"bad_u_no_name.csv", "bad_u_no_name.csv:1:18: u_:", "'u_<component>_<unit>'"},
        BadTable{"bad_u_c_not_closed.csv", "bad_u_c_not_closed.csv:5:10: u_epsilon_zc_urad:", "repeat the 0 deg value"}),
    [](const testing::TestParamInfo<BadTable>& param) {
      std::string name = param.param.file;
      name = name.substr(4, name.size() - 8); // strip "bad_" and ".csv"
      return name;
    });

TEST(ErrorTable, MissingFileIsNamed) {
  try {
    load_error_tables(data_path("no_such_table.csv"));
    FAIL();
  } catch (const geartopo::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_table.csv"), std::string::npos);
  }
}

TEST(ErrorTable, TableCoveringTheStrokeIsAccepted) {
  const MachineModel model(Strokes::skmc_1200w(), load_error_tables(data_path("x_axis.csv")));
  ErrorVector e;
  model.errors_at({450.0, 0.0, 0.0, 0.0, 0.0}, e);
  EXPECT_GT(e(index(ComponentId::delta_xx)), 5.2e-3); // between the rows at 400 and 500 mm
  EXPECT_LT(e(index(ComponentId::delta_xx)), 6.8e-3);
  Strokes longer = Strokes::skmc_1200w();
  longer.x_mm.max = 901.0;
  EXPECT_THROW(MachineModel(longer, load_error_tables(data_path("x_axis.csv"))), geartopo::InputError);
  Strokes a_wide = Strokes::skmc_1200w();
  a_wide.a_deg = {-46.0, 45.0};
  EXPECT_THROW(MachineModel(a_wide, {load_error_table(data_path("a_axis.csv"), ComponentId::epsilon_xa)}), geartopo::InputError);
}

TEST(ErrorSources, PolynomialAndConstantConvertTheirUnits) {
  // 1 µm + 0.01 µm/mm·x: at x = 100 mm, 2 µm = 0.002 mm; slope 1e-5 mm/mm.
  const ErrorSource p = ErrorSource::polynomial(ComponentId::delta_xx, {1.0, 0.01}, "um", "mm");
  EXPECT_NEAR(p.value(100.0), 2e-3, 1e-16);
  EXPECT_NEAR(p.rate(100.0), 1e-5, 1e-18);
  // 2 µrad/deg·α for A, evaluated at α in rad: at 10°, 20 µrad; slope 2e-6·180/π rad/rad.
  const ErrorSource a = ErrorSource::polynomial(ComponentId::epsilon_xa, {0.0, 2.0}, "urad", "deg");
  EXPECT_NEAR(a.value(10.0 * units::kRadPerDeg), 20e-6, 1e-18);
  EXPECT_NEAR(a.rate(0.3), 2e-6 * units::kDegPerRad, 1e-15);
  // Quadratic in mm with value in mm.
  const ErrorSource q = ErrorSource::polynomial(ComponentId::delta_zz, {0.0, 0.0, 1e-8}, "mm", "mm");
  EXPECT_NEAR(q.value(500.0), 2.5e-3, 1e-16);
  const ErrorSource c = ErrorSource::constant(ComponentId::S_xy, 12.0, "urad");
  EXPECT_NEAR(c.value(123.0), 12e-6, 1e-20);
  EXPECT_EQ(c.rate(123.0), 0.0);
  EXPECT_NEAR(ErrorSource::constant(ComponentId::E_XOC, 5.0, "um").value(0.0), 5e-3, 1e-18);
  EXPECT_NEAR(ErrorSource::constant(ComponentId::epsilon_zc, 1.0, "arcsec").value(0.0), 4.84813681109536e-6, 1e-18);
}

TEST(ErrorSources, RejectWrongUnitsAndShapes) {
  EXPECT_THROW(ErrorSource::constant(ComponentId::delta_xx, 1.0, "urad"), std::invalid_argument);
  EXPECT_THROW(ErrorSource::constant(ComponentId::S_xy, 1.0, "um"), std::invalid_argument);
  EXPECT_THROW(ErrorSource::constant(ComponentId::S_xy, 1.0, "furlong"), std::invalid_argument);
  EXPECT_THROW(ErrorSource::constant(ComponentId::S_xy, std::nan(""), "urad"), std::invalid_argument);
  EXPECT_THROW(ErrorSource::polynomial(ComponentId::delta_xx, {0.0, 1.0}, "um", "deg"), std::invalid_argument);
  EXPECT_THROW(ErrorSource::polynomial(ComponentId::epsilon_zc, {0.0, 1.0}, "urad", "deg"), std::invalid_argument);
  EXPECT_THROW(ErrorSource::polynomial(ComponentId::S_xz, {0.0, 1.0}, "urad", "mm"), std::invalid_argument);
  EXPECT_NO_THROW(ErrorSource::polynomial(ComponentId::epsilon_zc, {3.0}, "urad", "deg")); // a constant is periodic
}

TEST(MachineModelSources, AComponentGivenTwiceIsRejected) {
  EXPECT_THROW(MachineModel(Strokes::skmc_1200w(), {ErrorSource::constant(ComponentId::S_xy, 1.0, "urad"),
                                                    ErrorSource::constant(ComponentId::S_xy, 2.0, "urad")}),
               std::invalid_argument);
  Strokes empty = Strokes::skmc_1200w();
  empty.y_mm = {10.0, 10.0};
  EXPECT_THROW(MachineModel{empty}, std::invalid_argument);
}

TEST(ComponentTable, NamesAndOrder) {
  EXPECT_EQ(info(ComponentId::epsilon_zc).name, "epsilon_zc");
  EXPECT_EQ(component_from_name("E_XOC"), ComponentId::E_XOC);
  EXPECT_FALSE(component_from_name("delta_xq").has_value());
  for (int i = 0; i < kComponentCount; ++i) {
    const ComponentInfo& c = info(component_at(i));
    EXPECT_EQ(index(c.id), i);
    EXPECT_EQ(c.position_dependent, i < kMotionComponentCount) << c.name;
    EXPECT_EQ(component_from_name(c.name), c.id);
  }
}

} // namespace
} // namespace geartopo::machine
