// geartopo — CSV error-table reader with located messages. Units: file units in, mm and rad out.
#include "geartopo/machine/error_table.hpp"
#include "geartopo/files/input_file.hpp"

#include "geartopo/core/text_field.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

namespace geartopo::machine {

namespace {

using text::excerpt;

using text::Field;
using text::split_fields;

struct Column {
  ComponentId id;
  std::string field;
  double scale; // file unit → internal
  std::vector<double> values;
  bool length;      // δ (mm inside) or ε (rad inside): which physical bound applies
  bool uncertainty; // a `u_<component>_<unit>` column: the standard uncertainty of the component's column
};

// The prefix of a standard-uncertainty column: `u_delta_xx_um` is the uncertainty of `delta_xx` (no component name
// starts with "u_").
constexpr std::string_view kUncertaintyPrefix = "u_";

constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::string_view axis_letter(Axis axis) {
  constexpr std::array<std::string_view, kAxisCount> letters = {"x", "y", "z", "a", "c"};
  return letters[static_cast<std::size_t>(axis)];
}

} // namespace

std::vector<ErrorSource> parse_error_tables(std::string_view text, const std::string& source) {
  auto fail = [&](int line, int column, const std::string& field, const std::string& msg) -> InputError {
    return InputError(source, line, column, field, msg);
  };
  geartopo::text::strip_bom(text);

  int line_no = 0, header_line = 0;
  Axis axis = Axis::X;
  double position_scale = 1.0;
  std::string position_field, position_unit;
  std::vector<Column> columns;
  std::vector<double> positions;
  std::vector<int> row_lines;
  std::vector<int> last_row_columns; // character column of every field of the last data row

  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string_view::npos || line[first] == '#') {
      if (nl == text.size()) break;
      continue;
    }
    const std::vector<Field> fields = split_fields(line);

    if (header_line == 0) { // ---- header
      header_line = line_no;
      if (fields.size() < 2)
        throw fail(line_no, 1, "", "the header needs a position column and at least one error column, e.g. 'x_mm,delta_xx_um'");
      const Field& p = fields[0];
      position_field = std::string(p.text);
      const std::size_t us = p.text.find('_');
      const std::string_view letter = p.text.substr(0, us);
      const std::string_view unit = us == std::string_view::npos ? std::string_view{} : p.text.substr(us + 1);
      if (letter == "x") axis = Axis::X;
      else if (letter == "y") axis = Axis::Y;
      else if (letter == "z") axis = Axis::Z;
      else if (letter == "a") axis = Axis::A;
      else if (letter == "c") axis = Axis::C;
      else
        throw fail(line_no, p.column, position_field,
                   "the first column must be the axis position '<axis>_<unit>' with axis x, y, z, a or c");
      const auto ps = position_unit_scale(axis, unit);
      if (!ps) {
        if (unit.empty()) throw fail(line_no, p.column, position_field, "the position column has no unit");
        if (!is_known_unit(unit)) throw fail(line_no, p.column, position_field, fmt::format("unknown unit '{}'", excerpt(unit)));
        throw fail(line_no, p.column, position_field,
                   fmt::format("'{}' is not a position unit of axis {} (use {})", unit, axis_name(axis),
                               is_rotary(axis) ? "deg or rad" : "mm"));
      }
      position_scale = *ps;
      position_unit = std::string(unit);
      for (std::size_t k = 1; k < fields.size(); ++k) {
        const Field& f = fields[k];
        const std::string name(f.text);
        // A `u_` column is read like the component column it qualifies: the same component, axis and unit checks.
        const bool is_u = f.text.starts_with(kUncertaintyPrefix);
        const std::string_view spec = is_u ? f.text.substr(kUncertaintyPrefix.size()) : f.text;
        const std::size_t us2 = spec.rfind('_');
        if (us2 == std::string_view::npos || us2 == 0)
          throw fail(line_no, f.column, name,
                     is_u ? "an uncertainty column must be 'u_<component>_<unit>', e.g. 'u_delta_xx_um'"
                          : "an error column must be '<component>_<unit>', e.g. 'delta_xx_um'");
        const std::string_view stem = spec.substr(0, us2), vunit = spec.substr(us2 + 1);
        const auto id = component_from_name(stem);
        if (!id) {
          // "delta_xx" without a unit splits as stem "delta", unit "xx": say what is missing.
          if (component_from_name(spec))
            throw fail(line_no, f.column, name, "the error column has no unit (e.g. '_um' or '_urad')");
          throw fail(line_no, f.column, name, fmt::format("unknown error component '{}'", excerpt(stem)));
        }
        const ComponentInfo& c = info(*id);
        if (!c.position_dependent)
          throw fail(line_no, f.column, name, fmt::format("{} is position independent: give it as a constant, not a table", c.name));
        if (c.axis != axis)
          throw fail(line_no, f.column, name,
                     fmt::format("{} is a function of the {} position but the position column is '{}'", c.name,
                                 axis_name(c.axis), position_field));
        const auto vs = value_unit_scale(c.quantity, vunit);
        if (!vs) {
          if (!is_known_unit(vunit)) throw fail(line_no, f.column, name, fmt::format("unknown unit '{}'", excerpt(vunit)));
          throw fail(line_no, f.column, name,
                     fmt::format("unit '{}' does not fit {}, which is {} (use {})", vunit, c.name,
                                 c.quantity == Quantity::Length ? "a length" : "an angle", file_unit(c.quantity)));
        }
        for (const Column& other : columns)
          if (other.id == *id && other.uncertainty == is_u)
            throw fail(line_no, f.column, name,
                       fmt::format("second {}column for {}", is_u ? "uncertainty " : "", c.name));
        columns.push_back({*id, name, *vs, {}, c.quantity == Quantity::Length, is_u});
      }
      for (std::size_t k = 0; k < columns.size(); ++k) {
        const Column& u = columns[k];
        if (!u.uncertainty) continue;
        const bool has_values = std::any_of(columns.begin(), columns.end(),
                                            [&](const Column& c) { return c.id == u.id && !c.uncertainty; });
        if (!has_values) {
          const ComponentInfo& c = info(u.id);
          throw fail(line_no, fields[k + 1].column, u.field,
                     fmt::format("the standard uncertainty of {}, but the file has no {} column (e.g. '{}_{}'): an "
                                 "uncertainty column needs its component's values in the same file",
                                 c.name, c.name, c.name, file_unit(c.quantity)));
        }
      }
      if (nl == text.size()) break;
      continue;
    }

    // ---- data row
    if (fields.size() != columns.size() + 1) {
      const int col = fields.size() > columns.size() + 1 ? fields[columns.size() + 1].column
                                                         : static_cast<int>(line.size()) + 1;
      throw fail(line_no, col, "",
                 fmt::format("the row has {} fields, the header has {}", fields.size(), columns.size() + 1));
    }
    last_row_columns.clear();
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const Field& f = fields[k];
      last_row_columns.push_back(f.column);
      const std::string& fname = k == 0 ? position_field : columns[k - 1].field;
      if (f.text.empty()) throw fail(line_no, f.column, fname, "empty field");
      double v = 0.0;
      if (geartopo::text::parse_number(f.text, v) != std::errc())
        throw fail(line_no, f.column, fname, fmt::format("'{}' is not a number", excerpt(f.text)));
      if (!std::isfinite(v)) throw fail(line_no, f.column, fname, fmt::format("'{}' is not a finite number", excerpt(f.text)));
      if (k == 0) {
        if (!positions.empty() && !(v > positions.back()))
          throw fail(line_no, f.column, fname,
                     fmt::format("position {} is not greater than the previous one ({} on line {}): positions must "
                                 "be strictly increasing",
                                 f.text, positions.back(), row_lines.back()));
        positions.push_back(v);
        row_lines.push_back(line_no);
      } else {
        const Column& c = columns[k - 1];
        if (c.uncertainty && v < 0.0)
          throw fail(line_no, f.column, fname,
                     fmt::format("'{}' is negative: a standard uncertainty is ≥ 0", excerpt(f.text)));
        const double limit = c.length ? kMaxTableLengthMm : kMaxTableAngleRad;
        if (std::abs(v * c.scale) > limit)
          throw fail(line_no, f.column, fname,
                     fmt::format("'{}' is beyond ±{} (in the column's unit: ±{:g}), more than a geometric error of an "
                                 "axis can be (a wrong unit?)",
                                 excerpt(f.text), c.length ? "1 mm" : "10 mrad", limit / c.scale));
        columns[k - 1].values.push_back(v);
      }
    }
    if (nl == text.size()) break;
  }

  if (header_line == 0) throw fail(0, 0, "", "no header line (e.g. 'x_mm,delta_xx_um')");
  if (positions.size() < 2)
    throw fail(row_lines.empty() ? header_line : row_lines.back(), 1, "",
               fmt::format("{} data row{}: a table needs at least 2", positions.size(), positions.size() == 1 ? "" : "s"));

  const int first = row_lines.front(), last = row_lines.back();
  const bool periodic = axis == Axis::C;
  std::vector<double> x(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) x[i] = positions[i] * position_scale;
  if (periodic) {
    // One full turn, closed: [0, 360] deg. Accept rounding of 2π written in rad.
    if (std::abs(x.front()) > 1e-9)
      throw fail(first, 1, position_field,
                 fmt::format("a C table is periodic and must start at 0 (covering [0, 360] deg), not at {} {}",
                             positions.front(), position_unit));
    if (std::abs(x.back() - kTwoPi) > 1e-9)
      throw fail(last, 1, position_field,
                 fmt::format("a C table is periodic and must end at 360 deg (2π rad, repeating the 0 row), not at {} {}",
                             positions.back(), position_unit));
    x.front() = 0.0;
    x.back() = kTwoPi;
  }

  const auto ends = periodic ? CubicSpline::Ends::Periodic : CubicSpline::Ends::NotAKnot;
  const auto spline_of = [&](std::size_t k) { // column k in internal units, values and their uncertainties alike
    Column& col = columns[k];
    if (periodic) {
      const double a = col.values.front(), b = col.values.back();
      if (std::abs(b - a) > 1e-9 * std::max(1.0, std::abs(a))) {
        throw fail(last, last_row_columns[k + 1], col.field,
                   fmt::format("a periodic C table must repeat the 0 deg value at 360 deg: {} differs from {} on line {}",
                               b, a, first));
      }
      col.values.back() = a;
    }
    std::vector<double> y(col.values.size());
    for (std::size_t i = 0; i < y.size(); ++i) y[i] = col.values[i] * col.scale;
    return CubicSpline(x, std::move(y), ends);
  };

  std::vector<ErrorSource> out;
  out.reserve(columns.size());
  for (std::size_t k = 0; k < columns.size(); ++k) {
    const Column& col = columns[k];
    if (col.uncertainty) continue;
    TableOrigin origin{source, header_line, first, last, static_cast<int>(k) + 2, col.field, position_field,
                       position_unit, position_scale, 0, ""};
    const auto u = std::find_if(columns.begin(), columns.end(),
                                [&](const Column& c) { return c.uncertainty && c.id == col.id; });
    if (u == columns.end()) {
      out.push_back(ErrorSource::table(col.id, spline_of(k), std::move(origin)));
      continue;
    }
    const auto ku = static_cast<std::size_t>(u - columns.begin());
    origin.uncertainty_column = static_cast<int>(ku) + 2;
    origin.uncertainty_field = u->field;
    out.push_back(ErrorSource::table(col.id, spline_of(k), std::move(origin), spline_of(ku)));
  }
  return out;
}

std::vector<ErrorSource> load_error_tables(const std::filesystem::path& path) {
  return parse_error_tables(input::read_input_file(path, input::kMaxErrorTableBytes, "error table"), path.string());
}

ErrorSource load_error_table(const std::filesystem::path& path, ComponentId expected) {
  std::vector<ErrorSource> all = load_error_tables(path);
  for (ErrorSource& s : all)
    if (s.id() == expected) return std::move(s);
  const ComponentInfo& c = info(expected);
  const TableOrigin* o = all.front().origin();
  throw InputError(path.string(), o->header_line, 1, "",
                   fmt::format("no column for {} (expected a header field like '{}_{}' against '{}_{}')", c.name, c.name,
                               file_unit(c.quantity), axis_letter(c.axis),
                               is_rotary(c.axis) ? "deg" : "mm"));
}

} // namespace geartopo::machine
