// geartopo — the ISG/Beckhoff TF5280 volumetric compensation table (docs/compensation.md, "Controller table: ISG CSV").
#include "geartopo/compensation/isg_table.hpp"

#include "geartopo/files/atomic_write.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/machine/chain.hpp"
#include "geartopo/machine/kinematic_chain.hpp"
#include "geartopo/machine/transforms.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <ostream>
#include <stdexcept>

namespace geartopo::compensation {
namespace {

using machine::Axis;
using machine::ComponentId;

constexpr std::array<char, 3> kLinearDirections = {'X', 'Y', 'Z'};

/// "EXX EYX EZX EAX EBX ECX" for X: ISO 230-1 component errors, E + error direction + axis.
std::vector<std::string> component_error_names(Axis axis) {
  const char k = machine::axis_name(axis)[0];
  std::vector<std::string> names;
  for (const char d : {'X', 'Y', 'Z', 'A', 'B', 'C'}) names.push_back(fmt::format("E{}{}", d, k));
  return names;
}

/// A parameter is a length (mm) when its error direction is X, Y or Z: EXk, EYk, EZk and X0k, Y0k, Z0k.
bool is_length_parameter(const std::string& name) {
  const char direction = name.size() == 3 && name[0] == 'E' ? name[1] : name[0];
  return std::find(kLinearDirections.begin(), kLinearDirections.end(), direction) != kLinearDirections.end();
}

bool is_iso_parameter(const std::string& name) {
  constexpr std::string_view axes = "XYZABC";
  if (name.size() != 3) return false;
  const bool component = name[0] == 'E' && axes.find(name[1]) != std::string_view::npos;
  const bool position = axes.find(name[0]) != std::string_view::npos && name[1] == '0';
  return (component || position) && axes.find(name[2]) != std::string_view::npos;
}

/// The axis' range in internal units (mm or rad): its stroke; C one turn.
std::pair<double, double> axis_range(const machine::Strokes& s, Axis axis) {
  switch (axis) {
  case Axis::X: return {s.x_mm.min, s.x_mm.max};
  case Axis::Y: return {s.y_mm.min, s.y_mm.max};
  case Axis::Z: return {s.z_mm.min, s.z_mm.max};
  case Axis::A: return {units::rad_from_deg(s.a_deg.min), units::rad_from_deg(s.a_deg.max)};
  case Axis::C: return {0.0, 2.0 * std::numbers::pi};
  }
  return {0.0, 0.0};
}

/// Internal position (mm or rad) → the file's argument unit (mm or deg).
double argument_from_position(Axis axis, double p) { return machine::is_rotary(axis) ? units::deg_from_rad(p) : p; }

/// True when the values step evenly (within tol, in file units).
bool equidistant(const std::vector<double>& a, double tol) {
  if (a.size() < 2) return false;
  const double h = (a.back() - a.front()) / static_cast<double>(a.size() - 1);
  for (std::size_t i = 0; i + 1 < a.size(); ++i)
    if (!(std::abs(a[i + 1] - a[i] - h) <= tol) || !(a[i + 1] > a[i])) return false;
  return true;
}

struct AxisGrid {
  std::vector<double> positions; // internal units
  std::string how;                // for the block's comment
};

/// One axis as a block needs it: its pose slot, its letter, its range (internal units) and, for a rotary axis, the
/// offsets k (0..5) of its motion components across it, which turn with it.
struct BlockAxis {
  Axis slot;
  std::string name;
  double lo, hi;
  std::array<int, 4> across{};
};

/// The CFXZAY's axis: the machine model's strokes, A across y, z and C across x, y.
BlockAxis setting_axis(const machine::MachineModel& model, Axis axis) {
  const auto [lo, hi] = axis_range(model.strokes(), axis);
  return {axis, std::string(machine::axis_name(axis)), lo, hi,
          axis == Axis::A ? std::array<int, 4>{1, 2, 4, 5} : std::array<int, 4>{0, 1, 3, 4}};
}

/// The grid of one axis' block (see make_isg_table).
AxisGrid axis_grid(const machine::MachineModel& model, const BlockAxis& block_axis, const IsgOptions& options) {
  const Axis axis = block_axis.slot;
  const double lo = block_axis.lo, hi = block_axis.hi;
  const char* unit = machine::is_rotary(axis) ? "deg" : "mm";
  const double step = machine::is_rotary(axis) ? options.rotary_step_deg : options.linear_step_mm;
  std::vector<const machine::ErrorSource*> tables;
  bool polynomial = false;
  for (int k = 0; k < 6; ++k) {
    const auto& s = model.source(machine::motion_component(axis, k));
    if (s.kind() == machine::ErrorSource::Kind::Table) tables.push_back(&s);
    if (s.kind() == machine::ErrorSource::Kind::Polynomial) polynomial = true;
  }
  // A rotary axis' δ and ε across the axis (in its turning plane) are given in the turning body's axes; in the fixed
  // axes of the table they turn with the axis, so even constants must be sampled.
  bool turning = false;
  if (machine::is_rotary(axis))
    for (const int k : block_axis.across) turning = turning || !model.source(machine::motion_component(axis, k)).is_zero();
  if (tables.empty() && !polynomial && !turning)
    return {{lo, hi}, "all its components are constant: two records, the ends of the stroke"};

  if (!tables.empty() && !polynomial) {
    const auto& knots = tables.front()->spline()->knots();
    std::vector<double> arguments;
    for (const double p : knots) arguments.push_back(argument_from_position(axis, p));
    const bool shared = std::all_of(tables.begin(), tables.end(), [&](const machine::ErrorSource* t) {
      const auto& k = t->spline()->knots();
      if (k.size() != knots.size()) return false;
      for (std::size_t i = 0; i < k.size(); ++i)
        if (std::abs(argument_from_position(axis, k[i]) - arguments[i]) > options.limits.step_tolerance) return false;
      return true;
    });
    if (shared && equidistant(arguments, options.limits.step_tolerance)) {
      if (static_cast<int>(knots.size()) > options.limits.max_records) {
        const machine::TableOrigin& o = *tables.front()->origin();
        throw InputError(o.file, o.first_line, o.column, o.field,
                         fmt::format("{} records exceed the ISG table limit max_records = {} (the controller's "
                                     "vol_comp[i].max_records): give a coarser table or raise the controller's limit",
                                     knots.size(), options.limits.max_records));
      }
      return {knots, fmt::format("the knots of {} (equidistant, {} records, values as measured)", tables.front()->describe(),
                                 knots.size())};
    }
  }

  const double span = argument_from_position(axis, hi) - argument_from_position(axis, lo);
  const double records = std::max(2.0, std::ceil(span / step - 1e-9) + 1.0);
  if (records > options.limits.max_records)
    throw std::invalid_argument(fmt::format("ISG table: sampling {} every {:g} {} over {:g} {} needs {:.0f} records, more than "
                                            "max_records = {} (vol_comp[i].max_records): use a coarser step",
                                            block_axis.name, step, unit, span, unit, records,
                                            options.limits.max_records));
  const int n = static_cast<int>(records);
  AxisGrid g;
  for (int i = 0; i < n; ++i) g.positions.push_back(lo + (hi - lo) * i / (n - 1));
  std::string sources;
  for (const auto* t : tables) sources += (sources.empty() ? "" : ", ") + t->describe();
  g.how = tables.empty()
              ? fmt::format("sampled every {:g} {} ({})", span / (n - 1), unit,
                            polynomial ? "polynomials" : "constants in the turning body's axes, turned into fixed axes")
              : fmt::format("RESAMPLED every {:g} {} over the stroke from the splines of {} (its knots are not one "
                            "equidistant grid{}): ISG GRID interpolation needs equidistant arguments",
                            span / (n - 1), unit, sources, polynomial ? ", or polynomials share the axis" : "");
  return g;
}

void require_positive(double v, const char* what) {
  if (!(std::isfinite(v) && v > 0.0)) throw std::invalid_argument(fmt::format("ISG table: {} must be positive and finite, got {}", what, v));
}

/// A number with `decimals` places, left-aligned in `width`; a value that rounds to zero is written "0.000…", never "-0.000…".
std::string fixed(double v, int decimals, int width) {
  std::string t = fmt::format("{:.{}f}", v, decimals);
  if (t.front() == '-' && t.find_first_not_of("-0.") == std::string::npos) t.erase(0, 1);
  return fmt::format("{:<{}}", t, width);
}

std::string block_name(const IsgBlock& b, std::size_t i) {
  std::string header = b.argument;
  for (const auto& p : b.parameters) header += (header.empty() ? "" : " ") + p;
  return fmt::format("block {} '{}'", i + 1, header);
}

} // namespace

int IsgTable::records() const {
  int n = 0;
  for (const auto& b : blocks) n += static_cast<int>(b.values.size());
  return n;
}

Eigen::Matrix<double, 6, 1> iso_component_errors(const machine::MachineModel& model, Axis axis, double position) {
  Eigen::Matrix<double, 6, 1> own;
  for (int k = 0; k < 6; ++k) own(k) = model.source(machine::motion_component(axis, k)).value(position);
  if (!machine::is_rotary(axis)) return own;
  // δ and ε of a rotary axis are in the turning body's axes (A body: ZMA = S_A·Rx(α)·T(δ)·R(ε)·S_A⁻¹; table:
  // FMC = S_C·Rz(γ)·T(δ)·R(ε)); ISO 230-7 gives error motions in fixed axes: turn them by Rx(α) or Rz(γ).
  const Eigen::Matrix3d wRbody = axis == Axis::A ? machine::rot_x(position) : machine::rot_z(position);
  Eigen::Matrix<double, 6, 1> iso;
  iso << wRbody * own.head<3>(), wRbody * own.tail<3>();
  return iso;
}

IsgTable make_isg_table(const machine::MachineModel& model, const IsgOptions& options) {
  require_positive(options.linear_step_mm, "linear_step_mm");
  require_positive(options.rotary_step_deg, "rotary_step_deg");
  if (options.limits.max_records < 2) throw std::invalid_argument("ISG table: max_records must be at least 2");

  IsgTable table;
  table.comments = {
      "geartopo: ISO 230-1 error parameters of the CFXZAY grinder for the ISG kernel / Beckhoff TF5280 volumetric",
      "compensation (list file: file_format ISG_CSV, interpolation GRID). docs/compensation.md, 'Controller table'.",
      "Values: machine ERRORS, actual minus nominal (the controller derives the corrections): mm for offsets, rad for",
      "angles. Arguments: X, Y, Z in mm; A, C in deg. '#' starts a new block with its own header.",
      "Component errors E<direction><axis> of the axis' moving component, right-handed about the machine axes:",
      "X, Z: of the carriage in the machine frame; Y: in the A body's axes (Y is carried by A) [M];",
      "A: of the wheel head about the A axis line, in the fixed axes of the Z carriage; C: of the table, in the fixed",
      "machine axes. Position errors: X0C Y0C (C axis line position), A0C B0C (its tilt), C0C (C zero), Y0A Z0A B0A",
      "C0A A0A likewise for A; squareness as orientation errors of the axis lines: C0Y, A0Y (of Y), B0Z (of Z).",
      "A volumetric table corrects the tool position only: the orientation errors' flank deviation is reported by",
      "'geartopo compensate --isg-table' (tool centre point: the wheel centre [M]).",
  };
  for (const Axis axis : machine::kAxes) {
    const AxisGrid grid = axis_grid(model, setting_axis(model, axis), options);
    IsgBlock b;
    b.argument = std::string(machine::axis_name(axis));
    b.parameters = component_error_names(axis);
    b.comments.push_back(fmt::format("{} axis component errors against {} ({}): {}", b.argument, b.argument,
                                     machine::is_rotary(axis) ? "deg" : "mm", grid.how));
    for (const double p : grid.positions) {
      b.arguments.push_back(argument_from_position(axis, p));
      const auto iso = iso_component_errors(model, axis, p);
      b.values.emplace_back(iso.data(), iso.data() + 6);
    }
    table.blocks.push_back(std::move(b));
  }

  const auto constant = [&](ComponentId id) { return model.source(id).value(0.0); };
  IsgBlock c;
  c.comments.push_back("position errors (constants): rotary axis line locations (ISO 230-7) and squareness");
  c.parameters = {"X0C", "Y0C", "A0C", "B0C", "C0C", "Y0A", "Z0A", "B0A", "C0A", "A0A", "C0Y", "A0Y", "B0Z"};
  c.values.push_back({constant(ComponentId::E_XOC), constant(ComponentId::E_YOC), constant(ComponentId::E_AOC),
                      constant(ComponentId::E_BOC), constant(ComponentId::E_COC), constant(ComponentId::E_YOA),
                      constant(ComponentId::E_ZOA), constant(ComponentId::E_BOA), constant(ComponentId::E_COA),
                      constant(ComponentId::E_AOA),
                      // Y leans to −x by S_xy: ŷ turned about +z by +S_xy; to −z by S_zy: about +x by −S_zy.
                      constant(ComponentId::S_xy), -constant(ComponentId::S_zy),
                      // Z leans to −x by S_xz: ẑ turned about +y by −S_xz.
                      -constant(ComponentId::S_xz)});
  table.blocks.push_back(std::move(c));
  return table;
}

namespace {

/// ISO 230-1's name of a rotary axis' location error: E_XOC → X0C (direction, 0, axis).
std::string location_parameter(std::string_view name) { return fmt::format("{}0{}", name[2], name[4]); }

/// Refuses a chain whose axes ISG cannot name: its model has X, Y, Z and A, B, C.
void require_isg_letters(const machine::KinematicChain& chain) {
  constexpr std::string_view isg_axes = "XYZABC";
  for (const Axis slot : machine::kAxes) {
    const std::string& name = chain.axis(slot).name;
    if (name.size() != 1 || isg_axes.find(name[0]) == std::string_view::npos)
      throw std::invalid_argument(fmt::format("ISG table: the {} chain's axis '{}' is not one of the ISG model's axes "
                                              "X, Y, Z, A, B, C (P-VOLC-00007)", chain.name(), name));
  }
}

/// One axis of a chain as a block: its stroke (the spindle one turn) and, if rotary, the components across it.
BlockAxis chain_axis(const machine::KinematicChain& chain, const machine::Joint& j) {
  const machine::AxisSpec& spec = chain.axis(j.slot);
  BlockAxis a{j.slot, spec.name, 0.0, 2.0 * std::numbers::pi, {}};
  if (spec.stroke) a.lo = spec.stroke->min, a.hi = spec.stroke->max;
  if (j.kind == machine::AxisKind::Rotary)
    a.across = {j.perpendicular[0], j.perpendicular[1], 3 + j.perpendicular[0], 3 + j.perpendicular[1]};
  return a;
}

/// The component errors of joint j at its position (mm, rad) in the fixed axes of the body that carries it: a linear
/// axis' own; a rotary axis' δ and ε (in its turning body, E(δ, ε) after R_d(θ)) turned by R_d(θ).  // 6×1
Eigen::Matrix<double, 6, 1> chain_component_errors(const machine::MachineModel& model, const machine::Joint& j,
                                                   double position) {
  Eigen::Matrix<double, 6, 1> own;
  for (int k = 0; k < 6; ++k) own(k) = model.source(machine::motion_component(j.slot, k)).value(position);
  if (j.kind == machine::AxisKind::Linear) return own;
  const double t = j.sign * position;
  const Eigen::Matrix3d R = j.dir == 0 ? machine::rot_x(t) : j.dir == 1 ? machine::rot_y(t) : machine::rot_z(t);
  Eigen::Matrix<double, 6, 1> fixed;
  fixed << R * own.head<3>(), R * own.tail<3>();
  return fixed;
}

/// The position errors of a chain: each rotary axis line's offsets, tilts and zero under its ISO 230-7 name, and the
/// squareness of each linear axis k to an axis j before it as the orientation error of k's line: k travels along
/// d − S·u (u: the direction it leans away from), which is d turned by ω = S·(u × d), a turn about one machine axis.
IsgBlock chain_position_errors(const machine::MachineModel& model, const machine::KinematicChain& chain) {
  const auto constant = [&](int index) { return model.source(machine::component_at(index)).value(0.0); };
  IsgBlock c;
  c.comments.push_back(fmt::format("position errors (constants): rotary axis line locations (ISO 230-7) and {}",
                                   "squareness as the orientation errors of the linear axis lines"));
  c.values.emplace_back();
  for (const machine::Joint& j : chain.joints()) {
    if (j.kind == machine::AxisKind::Rotary) {
      for (int i = 0; i < 5; ++i) {
        c.parameters.push_back(location_parameter(chain.info(machine::component_at(j.location + i)).name));
        c.values.back().push_back(constant(j.location + i));
      }
      continue;
    }
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d(j.dir) = j.sign;
    for (int k = 0; k < j.squareness_count; ++k) {
      const Eigen::Vector3d axis = j.lean[static_cast<std::size_t>(k)].cross(d);
      Eigen::Index about = 0;
      axis.cwiseAbs().maxCoeff(&about);
      c.parameters.push_back(fmt::format("{}0{}", "ABC"[about], chain.axis(j.slot).name));
      c.values.back().push_back(axis(about) * constant(j.squareness[static_cast<std::size_t>(k)]));
    }
  }
  return c;
}

} // namespace

IsgTable make_isg_table(const machine::MachineModel& model, const machine::KinematicChain& chain,
                        const IsgOptions& options) {
  if (chain.is_setting_chain()) return make_isg_table(model, options);
  require_positive(options.linear_step_mm, "linear_step_mm");
  require_positive(options.rotary_step_deg, "rotary_step_deg");
  if (options.limits.max_records < 2) throw std::invalid_argument("ISG table: max_records must be at least 2");
  require_isg_letters(chain);
  std::string order;
  for (const auto& a : chain.spec().workpiece) order += a.name;
  for (const auto& a : chain.spec().tool) order += a.name;

  IsgTable table;
  table.comments = {
      fmt::format("geartopo: ISO 230-1 error parameters of the {} grinder for the ISG kernel / Beckhoff TF5280", chain.name()),
      "volumetric compensation (list file: file_format ISG_CSV, interpolation GRID). docs/compensation.md.",
      fmt::format("Kinematics: chain {} (the axes from the workpiece to the tool), workpiece_axes {} (P-VOLC-00007/8).",
                  order, chain.spec().workpiece.size()),
      "Values: machine ERRORS, actual minus nominal (the controller derives the corrections): mm for offsets, rad for",
      "angles. Arguments: linear axes in mm, rotary axes in deg. '#' starts a new block with its own header.",
      "Component errors E<direction><axis> of the axis' moving body relative to the body that carries it, in that",
      "body's axes (parallel to the machine axes at home), right-handed; on the workpiece side too: the table's own",
      "error, not the tool's relative to it [M]. A rotary axis' errors are turned into the fixed axes of its carrier.",
      "Position errors: <d>0<R> of each rotary axis line (offsets, tilts, zero); squareness as orientation errors",
      "<A|B|C>0<k> of the linear axis lines (the line turned right-handed about that machine axis).",
      "A volumetric table corrects the tool position only: the orientation errors' flank deviation is reported by",
      "'geartopo compensate --isg-table' (tool centre point: the wheel centre [M]).",
  };
  for (const machine::Joint& j : chain.joints()) {
    const BlockAxis axis = chain_axis(chain, j);
    const AxisGrid grid = axis_grid(model, axis, options);
    IsgBlock b;
    b.argument = axis.name;
    for (const char d : {'X', 'Y', 'Z', 'A', 'B', 'C'}) b.parameters.push_back(fmt::format("E{}{}", d, axis.name));
    b.comments.push_back(fmt::format("{} axis ({}, {} side) component errors against {} ({}): {}", axis.name,
                                     j.kind == machine::AxisKind::Rotary ? "rotary" : "linear",
                                     j.workpiece_side ? "workpiece" : "tool", axis.name,
                                     machine::is_rotary(j.slot) ? "deg" : "mm", grid.how));
    for (const double p : grid.positions) {
      b.arguments.push_back(argument_from_position(j.slot, p));
      const auto iso = chain_component_errors(model, j, p);
      b.values.emplace_back(iso.data(), iso.data() + 6);
    }
    table.blocks.push_back(std::move(b));
  }
  table.blocks.push_back(chain_position_errors(model, chain));
  return table;
}

void check_isg_table(const IsgTable& table, const IsgLimits& limits) {
  constexpr std::string_view argument_names = "XYZABC";
  for (std::size_t i = 0; i < table.blocks.size(); ++i) {
    const IsgBlock& b = table.blocks[i];
    const std::string name = block_name(b, i);
    const auto fail = [&](const std::string& why) { throw std::invalid_argument(fmt::format("ISG table, {}: {}", name, why)); };
    if (b.parameters.empty()) fail("no parameters");
    for (const auto& p : b.parameters)
      if (!is_iso_parameter(p)) fail(fmt::format("'{}' is not an ISO 230-1 parameter name (EXX … ECC, X0X … C0C)", p));
    if (b.argument.empty()) {
      if (b.values.size() != 1 || !b.arguments.empty()) fail("a block of constants has exactly one record and no argument");
    } else {
      if (b.argument.size() != 1 || argument_names.find(b.argument[0]) == std::string_view::npos)
        fail(fmt::format("argument '{}' is not one of X, Y, Z, A, B, C", b.argument));
      if (b.arguments.size() != b.values.size()) fail("one argument per record");
      if (b.arguments.size() < 2) fail("at least 2 records against an argument");
      const char* unit = argument_names.find(b.argument[0]) >= 3 ? "deg" : "mm";
      const double h = (b.arguments.back() - b.arguments.front()) / static_cast<double>(b.arguments.size() - 1);
      for (std::size_t r = 0; r < b.arguments.size(); ++r) {
        if (!std::isfinite(b.arguments[r])) fail(fmt::format("argument of record {} is not finite", r + 1));
        if (r == 0) continue;
        const double step = b.arguments[r] - b.arguments[r - 1];
        if (!(step > 0.0)) fail(fmt::format("arguments not increasing at record {} ({} {} after {} {})", r + 1, b.arguments[r], unit, b.arguments[r - 1], unit));
        if (std::abs(step - h) > limits.step_tolerance)
          fail(fmt::format("arguments not equidistant: records {}–{} step {:.9g} {}, the block's mean step {:.9g} {} "
                           "(tolerance {:g} {}); the controller's GRID interpolation needs an equidistant grid",
                           r, r + 1, step, unit, h, unit, limits.step_tolerance, unit));
      }
    }
    for (std::size_t r = 0; r < b.values.size(); ++r) {
      if (b.values[r].size() != b.parameters.size())
        fail(fmt::format("record {} has {} values for {} parameters", r + 1, b.values[r].size(), b.parameters.size()));
      for (const double v : b.values[r])
        if (!std::isfinite(v)) fail(fmt::format("record {} has a value that is not finite", r + 1));
    }
  }
  if (table.records() > limits.max_records) {
    std::size_t largest = 0;
    for (std::size_t i = 0; i < table.blocks.size(); ++i)
      if (table.blocks[i].values.size() > table.blocks[largest].values.size()) largest = i;
    throw std::invalid_argument(fmt::format(
        "ISG table: {} records exceed the controller's limit max_records = {} (vol_comp[i].max_records); the longest "
        "is {} with {} records: use coarser error tables or sampling steps, or raise the controller's limit",
        table.records(), limits.max_records, block_name(table.blocks[largest], largest), table.blocks[largest].values.size()));
  }
}

void write_isg_table(std::ostream& out, const IsgTable& table, const IsgLimits& limits) {
  check_isg_table(table, limits);
  for (const auto& c : table.comments) out << "// " << c << "\n";
  for (std::size_t i = 0; i < table.blocks.size(); ++i) {
    const IsgBlock& b = table.blocks[i];
    if (i > 0) out << "#\n";
    for (const auto& c : b.comments) out << "// " << c << "\n";
    std::string header = b.argument.empty() ? "" : fmt::format("{:<16}", b.argument);
    for (const auto& p : b.parameters) header += fmt::format("{:<18}", p);
    while (!header.empty() && header.back() == ' ') header.pop_back();
    out << header << "\n";
    for (std::size_t r = 0; r < b.values.size(); ++r) {
      std::string row = b.argument.empty() ? "" : fixed(b.arguments[r], 9, 16);
      for (std::size_t k = 0; k < b.parameters.size(); ++k)
        row += fixed(b.values[r][k], is_length_parameter(b.parameters[k]) ? 9 : 12, 18);
      while (!row.empty() && row.back() == ' ') row.pop_back();
      out << row << "\n";
    }
  }
}

void write_isg_table(const std::filesystem::path& file, const IsgTable& table, const IsgLimits& limits) {
  check_isg_table(table, limits); // refuse before a file is even started
  output::write_atomically(file, [&](std::ostream& out) { write_isg_table(out, table, limits); });
}

machine::Pose PositionCompensatedProcess::actual_wMg(const grinding::PathPoint& pp) const {
  const machine::Pose ideal = machine::ideal_wMg(pp.q);
  const machine::Pose actual = inner_.actual_wMg(pp);
  machine::Pose left = actual;
  // Keep the actual orientation; put the TCP where the ideal chain has it: left·tcp_g = ideal·tcp_g.
  left.translation() = ideal * tcp_g_ - actual.linear() * tcp_g_;
  return left;
}

machine::Vector6d PositionCompensatedProcess::error_twist_w(const grinding::PathPoint& pp) const {
  const machine::Vector6d inner = inner_.error_twist_w(pp);
  const Eigen::Vector3d tcp_w = machine::ideal_wMg(pp.q) * tcp_g_;
  machine::Vector6d left;
  left.tail<3>() = inner.tail<3>();
  left.head<3>() = tcp_w.cross(inner.tail<3>()); // δp + δθ × tcp_w = 0: the TCP does not move
  return left;
}

} // namespace geartopo::compensation
