#include "numpy_columns.hpp"

#include "geartopo/core/input_error.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include <map>
#include <utility>

namespace py = pybind11;

namespace geartopo::python {

WordColumn::WordColumn(std::size_t n, std::size_t width)
    // From numpy's own converter (dtype::from_args): py::dtype(string) parses a PEP 3118 format in Python.
    : array_(cached_array(py::dtype::from_args(py::str(fmt::format("<U{}", width))), n)),
      width_(width), data_(static_cast<char32_t*>(array_.mutable_data())) {}

namespace {


/// The columns of n rows, filled by index; `grid`: with row and col, `traces`: with the trace names, `roll`: with
/// the roll length.
struct Columns {
  Columns(std::size_t n, bool grid, bool traces, bool roll_length = true)
      : tooth(new_column<int>(n)), row(new_column<int>(grid ? n : 0)), col(new_column<int>(grid ? n : 0)),
        roll(new_column<double>(roll_length ? n : 0)), diameter(new_column<double>(n)), z(new_column<double>(n)),
        deviation(new_column<double>(n)), design(new_column<double>(n)), flank(n, kFlankWidth),
        trace(traces ? n : 0, kTraceWidth), grid_(grid), traces_(traces), roll_length_(roll_length) {}
  py::array_t<int> tooth, row, col;
  py::array_t<double> roll, diameter, z, deviation, design;
  WordColumn flank, trace;

  /// The dict of the CSV file's columns, in its order (docs/python.md).
  py::dict to_dict() const {
    py::dict out;
    out["tooth"] = tooth;
    out["flank"] = flank.array();
    if (traces_) out["trace"] = trace.array();
    if (grid_) out["row"] = row, out["col"] = col;
    if (roll_length_) out["roll_length_mm"] = roll;
    out["diameter_mm"] = diameter;
    out["z_mm"] = z;
    out["deviation_um"] = deviation;
    out["design_um"] = design;
    return out;
  }

private:
  bool grid_, traces_, roll_length_;
};

} // namespace

py::dict topology_columns(const std::vector<grinding::FlankTopology>& topo, grinding::GridKind kind) {
  const auto points = [kind](const grinding::FlankTopology& ft) -> const std::vector<grinding::GridPoint>& {
    return kind == grinding::GridKind::Topology ? ft.grid : ft.dense;
  };
  std::size_t n = 0;
  for (const auto& ft : topo) n += points(ft).size();
  Columns c(n, true, false);
  auto tooth = c.tooth.mutable_unchecked<1>(), row = c.row.mutable_unchecked<1>(), col = c.col.mutable_unchecked<1>();
  auto roll = c.roll.mutable_unchecked<1>(), d = c.diameter.mutable_unchecked<1>(), z = c.z.mutable_unchecked<1>();
  auto dev = c.deviation.mutable_unchecked<1>(), design = c.design.mutable_unchecked<1>();
  py::ssize_t i = 0;
  for (const auto& ft : topo)
    for (const auto& p : points(ft)) {
      tooth(i) = ft.tooth, row(i) = p.row, col(i) = p.col;
      roll(i) = p.roll_length_mm, d(i) = p.diameter_mm, z(i) = p.z_mm, dev(i) = p.deviation_um, design(i) = p.design_um;
      c.flank.set(static_cast<std::size_t>(i), to_string(ft.flank));
      ++i;
    }
  return c.to_dict();
}

py::dict traces_columns(const std::vector<grinding::FlankTopology>& topo) {
  std::size_t n = 0;
  for (const auto& ft : topo) n += ft.profile.size() + ft.helix.size();
  Columns c(n, false, true);
  auto tooth = c.tooth.mutable_unchecked<1>();
  auto roll = c.roll.mutable_unchecked<1>();
  auto d = c.diameter.mutable_unchecked<1>(), z = c.z.mutable_unchecked<1>();
  auto dev = c.deviation.mutable_unchecked<1>(), design = c.design.mutable_unchecked<1>();
  py::ssize_t i = 0;
  for (const auto& ft : topo)
    for (const auto* trace : {&ft.profile, &ft.helix})
      for (const auto& p : *trace) {
        tooth(i) = ft.tooth;
        roll(i) = p.roll_length_mm, d(i) = p.diameter_mm, z(i) = p.z_mm, dev(i) = p.deviation_um, design(i) = p.design_um;
        c.flank.set(static_cast<std::size_t>(i), to_string(ft.flank));
        c.trace.set(static_cast<std::size_t>(i), trace == &ft.profile ? "profile" : "helix");
        ++i;
      }
  return c.to_dict();
}

py::dict topology_row_columns(const std::vector<grinding::TopologyRow>& rows) {
  Columns c(rows.size(), true, false, false);
  auto tooth = c.tooth.mutable_unchecked<1>(), row = c.row.mutable_unchecked<1>(), col = c.col.mutable_unchecked<1>();
  auto d = c.diameter.mutable_unchecked<1>(), z = c.z.mutable_unchecked<1>();
  auto dev = c.deviation.mutable_unchecked<1>(), design = c.design.mutable_unchecked<1>();
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto i = static_cast<py::ssize_t>(k);
    const auto& r = rows[k];
    tooth(i) = r.tooth, row(i) = r.row, col(i) = r.col;
    d(i) = r.diameter_mm, z(i) = r.z_mm, dev(i) = r.deviation_um, design(i) = r.design_um;
    c.flank.set(k, to_string(r.flank));
  }
  return c.to_dict();
}

namespace {

py::object required(const py::dict& d, const char* key, const std::string& source) {
  if (!d.contains(key))
    throw InputError(source, 0, 0, key, fmt::format("no column '{}' (the columns of topology.csv: docs/python.md)", key));
  return d[key];
}

void check_length(long long& n, long long size, const char* key, const std::string& source) {
  if (n >= 0 && size != n)
    throw InputError(source, 0, 0, key, fmt::format("{} values, the other columns have {}", size, n));
  n = size;
}

template <class T>
py::array_t<T> typed_column(const py::dict& d, const char* key, const std::string& source, long long& n) {
  // Numbers only: numpy's cast would drop a complex value's imaginary part and read "1.5" strings as numbers.
  const py::array raw = py::array::ensure(required(d, key, source));
  if (!raw) throw InputError(source, 0, 0, key, "not a one-dimensional array of numbers");
  if (const char kind = raw.dtype().kind(); kind != 'i' && kind != 'u' && kind != 'f')
    throw InputError(source, 0, 0, key,
                     fmt::format("an array of {} is not an array of real numbers",
                                 py::str(raw.dtype()).cast<std::string>()));
  py::array_t<T, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(raw);
  } catch (const py::error_already_set&) {
    a = {};
  }
  if (!a || a.ndim() != 1)
    throw InputError(source, 0, 0, key, "not a one-dimensional array of numbers");
  check_length(n, a.shape(0), key, source);
  return a;
}

} // namespace

py::array_t<double> double_column(const py::dict& d, const char* key, const std::string& source, long long& n) {
  return typed_column<double>(d, key, source, n);
}

py::array_t<int> int_column(const py::dict& d, const char* key, const std::string& source, long long& n) {
  // Read as numbers and checked one by one: numpy's cast to int would make a tooth 1.5 tooth 1, and 2³² tooth 0.
  const py::array_t<double> numbers = typed_column<double>(d, key, source, n);
  const auto in = numbers.unchecked<1>();
  py::array_t<int> out(numbers.shape(0));
  auto w = out.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < in.shape(0); ++i) {
    const double v = in(i);
    if (!(std::isfinite(v) && v == std::floor(v) && std::abs(v) <= std::numeric_limits<int>::max()))
      throw InputError(source, static_cast<int>(i) + 1, 0, key,
                       fmt::format("{} is not a whole number of at most ±2³¹ (line: the 1-based element)", v));
    w(i) = static_cast<int>(v);
  }
  return out;
}

std::vector<std::string> word_list(const py::dict& d, const char* key, const std::string& source, long long& n) {
  std::vector<std::string> out;
  try {
    for (const auto& item : py::iter(required(d, key, source))) out.push_back(py::str(item).cast<std::string>());
  } catch (const py::error_already_set&) {
    throw InputError(source, 0, 0, key, "not a sequence of words");
  }
  check_length(n, static_cast<long long>(out.size()), key, source);
  return out;
}

namespace {

Flank flank_at(const std::vector<std::string>& words, std::size_t i, const std::string& source, const char* key) {
  const auto f = parse_flank(words[i]);
  if (!f)
    throw InputError(source, static_cast<int>(i) + 1, 0, key,
                     fmt::format("'{}' is not left or right (line: the 1-based element)", words[i]));
  return *f;
}

} // namespace

std::vector<grinding::FlankTopology> topology_from_columns(const py::dict& topo, const std::string& source) {
  std::vector<grinding::FlankTopology> out;
  std::map<std::pair<int, Flank>, std::size_t> index;
  const auto flank_of = [&](int tooth, Flank flank) -> grinding::FlankTopology& {
    const auto [it, added] = index.try_emplace({tooth, flank}, out.size());
    if (added) {
      out.emplace_back();
      out.back().tooth = tooth;
      out.back().flank = flank;
    }
    return out[it->second];
  };
  const auto read_grid = [&](const py::dict& d, const std::string& src, bool dense) {
    long long n = -1;
    const auto tooth = int_column(d, "tooth", src, n), row = int_column(d, "row", src, n), col = int_column(d, "col", src, n);
    const auto flanks = word_list(d, "flank", src, n);
    const auto roll = double_column(d, "roll_length_mm", src, n), dia = double_column(d, "diameter_mm", src, n);
    const auto z = double_column(d, "z_mm", src, n), dev = double_column(d, "deviation_um", src, n);
    const auto design = double_column(d, "design_um", src, n);
    for (py::ssize_t i = 0; i < n; ++i) {
      grinding::GridPoint p;
      p.row = row.at(i), p.col = col.at(i);
      p.roll_length_mm = roll.at(i), p.diameter_mm = dia.at(i), p.z_mm = z.at(i);
      p.deviation_um = dev.at(i), p.design_um = design.at(i);
      auto& ft = flank_of(tooth.at(i), flank_at(flanks, static_cast<std::size_t>(i), src, "flank"));
      (dense ? ft.dense : ft.grid).push_back(p);
    }
  };
  const bool traces_only = topo.contains("trace"); // a traces dict itself (synth(format="traces"))
  if (!traces_only) read_grid(topo, source, false);
  const auto nested = [&](const char* key) {
    const py::object o = topo[key];
    if (!py::isinstance<py::dict>(o))
      throw InputError(source, 0, 0, key, fmt::format("{} is not a dict of arrays", py::repr(o).cast<std::string>()));
    return o.cast<py::dict>();
  };
  if (topo.contains("dense")) read_grid(nested("dense"), source + "['dense']", true);
  if (traces_only || topo.contains("traces")) {
    const std::string src = traces_only ? source : source + "['traces']";
    const py::dict t = traces_only ? topo : nested("traces");
    long long n = -1;
    const auto tooth = int_column(t, "tooth", src, n);
    const auto flanks = word_list(t, "flank", src, n), traces = word_list(t, "trace", src, n);
    const auto roll = double_column(t, "roll_length_mm", src, n), dia = double_column(t, "diameter_mm", src, n);
    const auto z = double_column(t, "z_mm", src, n), dev = double_column(t, "deviation_um", src, n);
    const auto design = double_column(t, "design_um", src, n);
    for (py::ssize_t i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (traces[k] != "profile" && traces[k] != "helix")
        throw InputError(src, static_cast<int>(i) + 1, 0, "trace",
                         fmt::format("'{}' is not profile or helix (line: the 1-based element)", traces[k]));
      grinding::TracePoint p;
      p.roll_length_mm = roll.at(i), p.diameter_mm = dia.at(i), p.z_mm = z.at(i);
      p.deviation_um = dev.at(i), p.design_um = design.at(i);
      auto& ft = flank_of(tooth.at(i), flank_at(flanks, k, src, "flank"));
      (traces[k] == "profile" ? ft.profile : ft.helix).push_back(p);
    }
  }
  return out;
}

} // namespace geartopo::python
