#include "measured_input.hpp"
#include "arguments.hpp"
#include "interrupt.hpp"
#include "numpy_columns.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/measurement/any_measurement.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <set>
#include <tuple>

namespace py = pybind11;

namespace geartopo::python {
namespace {

constexpr const char* kArraysSource = "measured arrays";

/// Rows of a dict of columns, with the topology reader's checks (grinding/topology_csv.hpp): finite numbers, a known
/// flank, tooth 1..z, |deviation| and |design| ≤ kMaxDeviationUm, positive diameter, grid indices ≥ 1 when given,
/// no (tooth, flank, row, col) twice. line = the 1-based element.
std::vector<grinding::TopologyRow> rows_of(const py::dict& d, int teeth) {
  const std::string src = kArraysSource;
  long long n = -1;
  const auto tooth = int_column(d, "tooth", src, n);
  const auto flanks = word_list(d, "flank", src, n);
  const auto dia = double_column(d, "diameter_mm", src, n), z = double_column(d, "z_mm", src, n);
  const auto dev = double_column(d, "deviation_um", src, n);
  const bool grid = d.contains("row") || d.contains("col");
  std::optional<py::array_t<int>> row, col;
  if (grid) {
    row = int_column(d, "row", src, n);
    col = int_column(d, "col", src, n);
  }
  std::optional<py::array_t<double>> design;
  if (d.contains("design_um")) design = double_column(d, "design_um", src, n);
  std::vector<grinding::TopologyRow> rows;
  rows.reserve(static_cast<std::size_t>(n));
  std::set<std::tuple<int, Flank, int, int>> seen;
  for (py::ssize_t i = 0; i < n; ++i) {
    const int line = static_cast<int>(i) + 1;
    const auto fail = [&](const char* field, const std::string& msg) { throw InputError(src, line, 0, field, msg); };
    grinding::TopologyRow r;
    r.line = line;
    r.tooth = tooth.at(i);
    if (r.tooth < 1 || r.tooth > teeth) fail("tooth", fmt::format("{} is not a tooth of 1..{}", r.tooth, teeth));
    const auto f = parse_flank(flanks[static_cast<std::size_t>(i)]);
    if (!f) fail("flank", fmt::format("'{}' is not left or right", flanks[static_cast<std::size_t>(i)]));
    r.flank = *f;
    r.diameter_mm = dia.at(i), r.z_mm = z.at(i), r.deviation_um = dev.at(i);
    r.design_um = design ? design->at(i) : 0.0;
    if (!std::isfinite(r.diameter_mm) || r.diameter_mm <= 0.0)
      fail("diameter_mm", fmt::format("{} is not a positive finite number", r.diameter_mm));
    if (!std::isfinite(r.z_mm)) fail("z_mm", fmt::format("{} is not finite", r.z_mm));
    for (const auto& [field, v] : {std::pair{"deviation_um", r.deviation_um}, std::pair{"design_um", r.design_um}}) {
      if (!std::isfinite(v)) fail(field, fmt::format("{} is not finite", v));
      if (std::abs(v) > grinding::kMaxDeviationUm)
        fail(field, fmt::format("{} µm is beyond ±{} µm, more than a ground flank can deviate (a wrong unit?)", v,
                                grinding::kMaxDeviationUm));
    }
    if (grid) {
      r.row = row->at(i), r.col = col->at(i);
      if (r.row < 1) fail("row", fmt::format("{} is not a grid row ≥ 1", r.row));
      if (r.col < 1) fail("col", fmt::format("{} is not a grid column ≥ 1", r.col));
      if (!seen.insert({r.tooth, r.flank, r.row, r.col}).second)
        fail("row", fmt::format("tooth {} {} row {} col {} is given twice", r.tooth, to_string(r.flank), r.row, r.col));
    }
    rows.push_back(r);
  }
  if (rows.empty()) throw InputError(src, 0, 0, "", "no points");
  return rows;
}

} // namespace

measurement::MeasuredAgainst measured_against_argument(const py::object& against) {
  if (against.is_none()) return measurement::MeasuredAgainst::as_file;
  if (!py::isinstance<py::str>(against))
    throw py::type_error(fmt::format("measured_against: {} is not \"design\", \"involute\" or None",
                                     py::repr(against).cast<std::string>()));
  const auto word = against.cast<std::string>();
  const auto parsed = measurement::parse_measured_against(word);
  if (!parsed)
    throw py::value_error(fmt::format("measured_against: \"{}\" is not \"design\", \"involute\" or None", word));
  return *parsed;
}

std::vector<measurement::MeasuredPoint> measured_points(const PyScene& scene, const py::object& measured, std::string& name,
                                                        measurement::MeasuredAgainst against) {
  const auto& setup = scene.wb->setup;
  if (py::isinstance<py::dict>(measured)) {
    name = kArraysSource;
    const auto columns = measured.cast<py::dict>();
    if (against != measurement::MeasuredAgainst::as_file && columns.contains("design_um"))
      throw py::value_error(fmt::format("measured_against: the arrays say what their deviations are measured from "
                                        "(their design_um column): \"{}\" is for arrays without one",
                                        measurement::to_string(against)));
    auto points = measurement::measured_points(rows_of(columns, setup.geometry().teeth()), setup.geometry(), kArraysSource);
    if (!columns.contains("design_um")) measurement::declare_reference(points, against, setup.design());
    measurement::refer_to_design(points, setup.design()); // as read_any_measurement refers a file's
    return points;
  }
  if (!py::isinstance<py::str>(measured) && !py::hasattr(measured, "__fspath__"))
    throw py::type_error(fmt::format("measured: {} is not a measurement: a path (str or os.PathLike) or a dict of "
                                     "arrays", py::repr(measured).cast<std::string>()));
  name = path_argument(measured, "measured");
  // As the CLI (app/measurement_options.cpp): the scene's key for the scene's own measurement when nothing is said.
  const auto& grid = scene.wb->scene.grid;
  if (against == measurement::MeasuredAgainst::as_file && !grid.measured_against.empty() && name == grid.measured_file)
    against = measurement::parse_measured_against(grid.measured_against).value_or(measurement::MeasuredAgainst::as_file);
  std::vector<std::string> warnings;
  std::vector<measurement::MeasuredPoint> points;
  {
    const LibraryWork work; // Ctrl-C caught, the GIL released
    measurement::KlingelnbergOptions mka; // the default reader options, with the Ctrl-C check (a 64 MB export: seconds)
    mka.keep_going = interrupt_check();
    points = measurement::read_any_measurement(name, setup, &warnings, mka, nullptr, against);
  }
  if (!warnings.empty()) {
    const auto warn = py::module_::import("warnings").attr("warn");
    for (const auto& w : warnings) warn(w);
  }
  return points;
}

} // namespace geartopo::python
