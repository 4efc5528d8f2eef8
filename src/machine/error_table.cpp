// geartopo — CSV error-table reader with located messages. Units: file units in, mm and rad out.
#include "geartopo/machine/error_table.hpp"
#include "geartopo/files/input_file.hpp"

#include "geartopo/core/text_field.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
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

/// An error table read line by line: the header (the position column, then the error and uncertainty columns), the
/// data rows, then one spline per column.
class TableParser {
public:
  TableParser(const std::string& source, const KinematicChain& chain) : source_(source), chain_(chain) {}
  std::vector<ErrorSource> parse(std::string_view text);

private:
  InputError fail(int line, int column, const std::string& field, const std::string& msg) const {
    return InputError(source_, line, column, field, msg);
  }
  void read_header(const std::vector<Field>& fields);
  /// The first column, '<axis>_<unit>': the axis and the unit of its positions.
  void read_position_column(const Field& p);
  /// An error column '<component>_<unit>' or its uncertainty 'u_<component>_<unit>'.
  void read_error_column(const Field& f);
  void read_row(std::string_view line, const std::vector<Field>& fields);
  /// The positions in internal units (mm, rad); a C table checked to cover one closed turn.
  std::vector<double> internal_positions() const;
  /// Column k in internal units, values and their uncertainties alike; a C table's column checked to repeat its
  /// 0 deg value at 360 deg.
  CubicSpline spline_of(std::size_t k, const std::vector<double>& x);
  std::vector<ErrorSource> sources();

  const std::string& source_;
  const KinematicChain& chain_; // names the components and the axes
  int line_no_ = 0, header_line_ = 0;
  Axis axis_ = Axis::X;
  double position_scale_ = 1.0;
  std::string position_field_, position_unit_;
  std::vector<Column> columns_;
  std::vector<double> positions_;
  std::vector<int> row_lines_;
  std::vector<int> last_row_columns_; // character column of every field of the last data row
};

std::vector<ErrorSource> TableParser::parse(std::string_view text) {
  geartopo::text::strip_bom(text);
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no_;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::size_t first = line.find_first_not_of(" \t");
    if (first != std::string_view::npos && line[first] != '#') {
      const std::vector<Field> fields = split_fields(line);
      if (header_line_ == 0)
        read_header(fields);
      else
        read_row(line, fields);
    }
    if (nl == text.size()) break;
  }
  return sources();
}

void TableParser::read_header(const std::vector<Field>& fields) {
  header_line_ = line_no_;
  if (fields.size() < 2)
    throw fail(line_no_, 1, "", "the header needs a position column and at least one error column, e.g. 'x_mm,delta_xx_um'");
  read_position_column(fields[0]);
  for (std::size_t k = 1; k < fields.size(); ++k) read_error_column(fields[k]);
  for (std::size_t k = 0; k < columns_.size(); ++k) {
    const Column& u = columns_[k];
    if (!u.uncertainty) continue;
    const bool has_values = std::any_of(columns_.begin(), columns_.end(),
                                        [&](const Column& c) { return c.id == u.id && !c.uncertainty; });
    if (!has_values) {
      const ComponentInfo& c = chain_.info(u.id);
      throw fail(line_no_, fields[k + 1].column, u.field,
                 fmt::format("the standard uncertainty of {}, but the file has no {} column (e.g. '{}_{}'): an "
                             "uncertainty column needs its component's values in the same file",
                             c.name, c.name, c.name, file_unit(c.quantity)));
    }
  }
}

void TableParser::read_position_column(const Field& p) {
  position_field_ = std::string(p.text);
  const std::size_t us = p.text.find('_');
  const std::string_view letter = p.text.substr(0, us);
  const std::string_view unit = us == std::string_view::npos ? std::string_view{} : p.text.substr(us + 1);
  // The chain's axis letters in lower case (x, y, z, a, c on the CFXZAY); the slot of the one named.
  std::string letters;
  bool found = false;
  for (int s = 0; s < kAxisCount; ++s) {
    std::string l(chain_.axis_name(static_cast<Axis>(s)));
    for (char& ch : l) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    letters += (s == 0 ? "" : s == kAxisCount - 1 ? " or " : ", ") + l;
    if (letter == l) axis_ = static_cast<Axis>(s), found = true;
  }
  if (!found)
    throw fail(line_no_, p.column, position_field_,
               fmt::format("the first column must be the axis position '<axis>_<unit>' with axis {}", letters));
  const auto ps = position_unit_scale(axis_, unit);
  if (!ps) {
    if (unit.empty()) throw fail(line_no_, p.column, position_field_, "the position column has no unit");
    if (!is_known_unit(unit)) throw fail(line_no_, p.column, position_field_, fmt::format("unknown unit '{}'", excerpt(unit)));
    throw fail(line_no_, p.column, position_field_,
               fmt::format("'{}' is not a position unit of axis {} (use {})", unit, chain_.axis_name(axis_),
                           is_rotary(axis_) ? "deg or rad" : "mm"));
  }
  position_scale_ = *ps;
  position_unit_ = std::string(unit);
}

void TableParser::read_error_column(const Field& f) {
  const std::string name(f.text);
  // A `u_` column is read like the component column it qualifies: the same component, axis and unit checks.
  const bool is_u = f.text.starts_with(kUncertaintyPrefix);
  const std::string_view spec = is_u ? f.text.substr(kUncertaintyPrefix.size()) : f.text;
  const std::size_t us = spec.rfind('_');
  if (us == std::string_view::npos || us == 0)
    throw fail(line_no_, f.column, name,
               is_u ? "an uncertainty column must be 'u_<component>_<unit>', e.g. 'u_delta_xx_um'"
                    : "an error column must be '<component>_<unit>', e.g. 'delta_xx_um'");
  const std::string_view stem = spec.substr(0, us), vunit = spec.substr(us + 1);
  const auto id = chain_.component_from_name(stem);
  if (!id) {
    // "delta_xx" without a unit splits as stem "delta", unit "xx": say what is missing.
    if (chain_.component_from_name(spec))
      throw fail(line_no_, f.column, name, "the error column has no unit (e.g. '_um' or '_urad')");
    throw fail(line_no_, f.column, name,
               fmt::format("unknown error component '{}'{}", excerpt(stem),
                           &chain_ == &cfxzay() ? "" : " of the " + chain_.name() + " chain"));
  }
  const ComponentInfo& c = chain_.info(*id);
  if (!c.position_dependent)
    throw fail(line_no_, f.column, name, fmt::format("{} is position independent: give it as a constant, not a table", c.name));
  if (c.axis != axis_)
    throw fail(line_no_, f.column, name,
               fmt::format("{} is a function of the {} position but the position column is '{}'", c.name,
                           chain_.axis_name(c.axis), position_field_));
  const auto vs = value_unit_scale(c.quantity, vunit);
  if (!vs) {
    if (!is_known_unit(vunit)) throw fail(line_no_, f.column, name, fmt::format("unknown unit '{}'", excerpt(vunit)));
    throw fail(line_no_, f.column, name,
               fmt::format("unit '{}' does not fit {}, which is {} (use {})", vunit, c.name,
                           c.quantity == Quantity::Length ? "a length" : "an angle", file_unit(c.quantity)));
  }
  for (const Column& other : columns_)
    if (other.id == *id && other.uncertainty == is_u)
      throw fail(line_no_, f.column, name, fmt::format("second {}column for {}", is_u ? "uncertainty " : "", c.name));
  columns_.push_back({*id, name, *vs, {}, c.quantity == Quantity::Length, is_u});
}

void TableParser::read_row(std::string_view line, const std::vector<Field>& fields) {
  if (fields.size() != columns_.size() + 1) {
    const int col = fields.size() > columns_.size() + 1 ? fields[columns_.size() + 1].column : static_cast<int>(line.size()) + 1;
    throw fail(line_no_, col, "", fmt::format("the row has {} fields, the header has {}", fields.size(), columns_.size() + 1));
  }
  last_row_columns_.clear();
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const Field& f = fields[k];
    last_row_columns_.push_back(f.column);
    const std::string& fname = k == 0 ? position_field_ : columns_[k - 1].field;
    if (f.text.empty()) throw fail(line_no_, f.column, fname, "empty field");
    double v = 0.0;
    if (geartopo::text::parse_number(f.text, v) != std::errc())
      throw fail(line_no_, f.column, fname, fmt::format("'{}' is not a number", excerpt(f.text)));
    if (!std::isfinite(v)) throw fail(line_no_, f.column, fname, fmt::format("'{}' is not a finite number", excerpt(f.text)));
    if (k == 0) {
      if (!positions_.empty() && !(v > positions_.back()))
        throw fail(line_no_, f.column, fname,
                   fmt::format("position {} is not greater than the previous one ({} on line {}): positions must "
                               "be strictly increasing",
                               f.text, positions_.back(), row_lines_.back()));
      positions_.push_back(v);
      row_lines_.push_back(line_no_);
      continue;
    }
    const Column& c = columns_[k - 1];
    if (c.uncertainty && v < 0.0)
      throw fail(line_no_, f.column, fname, fmt::format("'{}' is negative: a standard uncertainty is ≥ 0", excerpt(f.text)));
    const double limit = c.length ? kMaxTableLengthMm : kMaxTableAngleRad;
    if (std::abs(v * c.scale) > limit)
      throw fail(line_no_, f.column, fname,
                 fmt::format("'{}' is beyond ±{} (in the column's unit: ±{:g}), more than a geometric error of an "
                             "axis can be (a wrong unit?)",
                             excerpt(f.text), c.length ? "1 mm" : "10 mrad", limit / c.scale));
    columns_[k - 1].values.push_back(v);
  }
}

std::vector<double> TableParser::internal_positions() const {
  std::vector<double> x(positions_.size());
  for (std::size_t i = 0; i < positions_.size(); ++i) x[i] = positions_[i] * position_scale_;
  if (axis_ == Axis::C) {
    // One full turn, closed: [0, 360] deg. Accept rounding of 2π written in rad.
    if (std::abs(x.front()) > 1e-9)
      throw fail(row_lines_.front(), 1, position_field_,
                 fmt::format("a C table is periodic and must start at 0 (covering [0, 360] deg), not at {} {}",
                             positions_.front(), position_unit_));
    if (std::abs(x.back() - kTwoPi) > 1e-9)
      throw fail(row_lines_.back(), 1, position_field_,
                 fmt::format("a C table is periodic and must end at 360 deg (2π rad, repeating the 0 row), not at {} {}",
                             positions_.back(), position_unit_));
    x.front() = 0.0;
    x.back() = kTwoPi;
  }
  return x;
}

CubicSpline TableParser::spline_of(std::size_t k, const std::vector<double>& x) {
  Column& col = columns_[k];
  const bool periodic = axis_ == Axis::C;
  if (periodic) {
    const double a = col.values.front(), b = col.values.back();
    if (std::abs(b - a) > 1e-9 * std::max(1.0, std::abs(a)))
      throw fail(row_lines_.back(), last_row_columns_[k + 1], col.field,
                 fmt::format("a periodic C table must repeat the 0 deg value at 360 deg: {} differs from {} on line {}",
                             b, a, row_lines_.front()));
    col.values.back() = a;
  }
  std::vector<double> y(col.values.size());
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = col.values[i] * col.scale;
  return CubicSpline(x, std::move(y), periodic ? CubicSpline::Ends::Periodic : CubicSpline::Ends::NotAKnot);
}

std::vector<ErrorSource> TableParser::sources() {
  if (header_line_ == 0) throw fail(0, 0, "", "no header line (e.g. 'x_mm,delta_xx_um')");
  if (positions_.size() < 2)
    throw fail(row_lines_.empty() ? header_line_ : row_lines_.back(), 1, "",
               fmt::format("{} data row{}: a table needs at least 2", positions_.size(), positions_.size() == 1 ? "" : "s"));
  const std::vector<double> x = internal_positions();
  std::vector<ErrorSource> out;
  out.reserve(columns_.size());
  for (std::size_t k = 0; k < columns_.size(); ++k) {
    const Column& col = columns_[k];
    if (col.uncertainty) continue;
    TableOrigin origin{source_, header_line_, row_lines_.front(), row_lines_.back(), static_cast<int>(k) + 2, col.field,
                       position_field_, position_unit_, position_scale_, 0, ""};
    const auto u = std::find_if(columns_.begin(), columns_.end(),
                                [&](const Column& c) { return c.uncertainty && c.id == col.id; });
    if (u == columns_.end()) {
      out.push_back(ErrorSource::table(col.id, spline_of(k, x), std::move(origin)));
      continue;
    }
    const auto ku = static_cast<std::size_t>(u - columns_.begin());
    origin.uncertainty_column = static_cast<int>(ku) + 2;
    origin.uncertainty_field = u->field;
    out.push_back(ErrorSource::table(col.id, spline_of(k, x), std::move(origin), spline_of(ku, x)));
  }
  return out;
}

} // namespace

std::vector<ErrorSource> parse_error_tables(std::string_view text, const std::string& source,
                                           const KinematicChain& chain) {
  return TableParser(source, chain).parse(text);
}

std::vector<ErrorSource> load_error_tables(const std::filesystem::path& path, const KinematicChain& chain) {
  return parse_error_tables(input::read_input_file(path, input::kMaxErrorTableBytes, "error table"), path.string(),
                            chain);
}

std::vector<ErrorSource> load_error_tables(const std::filesystem::path& path) { return load_error_tables(path, cfxzay()); }

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
