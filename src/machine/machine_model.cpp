// geartopo — MachineModel: validation of strokes and sources, evaluation of the error vector. Units: mm, rad.
#include "geartopo/machine/machine_model.hpp"
#include "geartopo/core/units.hpp"

#include "geartopo/machine/error_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace geartopo::machine {

namespace {


void check_interval(const Interval& i, std::string_view what) {
  if (!std::isfinite(i.min) || !std::isfinite(i.max) || !(i.max > i.min))
    throw std::invalid_argument(fmt::format("stroke {}: [{}, {}] is not a finite, non-empty interval", what, i.min, i.max));
}

/// Stroke of a linear or the A axis in internal units (mm or rad).
Interval internal_stroke(const Strokes& s, Axis axis) {
  switch (axis) {
  case Axis::X: return s.x_mm;
  case Axis::Y: return s.y_mm;
  case Axis::Z: return s.z_mm;
  case Axis::A: return {s.a_deg.min * units::kRadPerDeg, s.a_deg.max * units::kRadPerDeg};
  case Axis::C: break;
  }
  return {0.0, 2.0 * std::numbers::pi};
}

} // namespace

namespace {

std::uint64_t next_model_id() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

} // namespace

MachineModel::MachineModel(const Strokes& strokes) : MachineModel(strokes, {}) {}

MachineModel::MachineModel(const Strokes& strokes, std::vector<ErrorSource> sources)
    : strokes_(strokes), id_(next_model_id()) {
  check_interval(strokes.x_mm, "X (mm)");
  check_interval(strokes.y_mm, "Y (mm)");
  check_interval(strokes.z_mm, "Z (mm)");
  check_interval(strokes.a_deg, "A (deg)");
  sources_.reserve(kComponentCount);
  for (int i = 0; i < kComponentCount; ++i) sources_.push_back(ErrorSource::zero(component_at(i)));
  std::vector<bool> given(kComponentCount, false);
  for (ErrorSource& s : sources) {
    const auto k = static_cast<std::size_t>(index(s.id()));
    if (given[k])
      throw std::invalid_argument(fmt::format("{} is given twice: {} and {}", info(s.id()).name,
                                              sources_[k].describe(), s.describe()));
    given[k] = true;
    check_coverage(s);
    sources_[k] = std::move(s);
  }
  for (int i = 0; i < kComponentCount; ++i) {
    const ComponentInfo& c = info(component_at(i));
    if (!c.position_dependent) continue;
    AxisComponents& axis = varying_on_[static_cast<std::size_t>(c.axis)];
    const CubicSpline* spline = sources_[static_cast<std::size_t>(i)].spline();
    if (!spline) {
      axis.others.push_back(i);
      continue;
    }
    const auto same_knots = [&](const std::vector<int>& group) {
      return sources_[static_cast<std::size_t>(group.front())].spline()->knots() == spline->knots();
    };
    const auto group = std::find_if(axis.shared_knots.begin(), axis.shared_knots.end(), same_knots);
    if (group == axis.shared_knots.end()) axis.shared_knots.push_back({i});
    else group->push_back(i);
  }
}

void MachineModel::check_coverage(const ErrorSource& s) const {
  const TableOrigin* o = s.origin();
  if (!o) return;
  const Axis axis = info(s.id()).axis;
  if (axis == Axis::C) return; // periodic over [0, 360] deg, checked by the reader
  const Interval st = internal_stroke(strokes_, axis);
  const CubicSpline& sp = *s.spline();
  const double tol = 1e-9 * std::max(1.0, std::abs(st.max - st.min));
  const double k = 1.0 / o->position_scale; // internal → file unit
  const auto stroke_text = [&] {
    return fmt::format("the {} stroke [{:g}, {:g}] {}", axis_name(axis), st.min * k, st.max * k, o->position_unit);
  };
  if (sp.front() > st.min + tol)
    throw InputError(o->file, o->first_line, 1, o->position_field,
                     fmt::format("column {} '{}' starts at {:g} {}, inside {}: the table must cover the stroke",
                                 o->column, o->field, sp.front() * k, o->position_unit, stroke_text()));
  if (sp.back() < st.max - tol)
    throw InputError(o->file, o->last_line, 1, o->position_field,
                     fmt::format("column {} '{}' ends at {:g} {}, inside {}: the table must cover the stroke",
                                 o->column, o->field, sp.back() * k, o->position_unit, stroke_text()));
}

bool MachineModel::within_strokes(const AxisPose& q) const {
  for (Axis axis : {Axis::X, Axis::Y, Axis::Z, Axis::A}) {
    const Interval st = internal_stroke(strokes_, axis);
    if (!(q[axis] >= st.min && q[axis] <= st.max)) return false;
  }
  return true;
}

void MachineModel::errors_at(const AxisPose& q, ErrorVector& e) const noexcept {
  for (int i = 0; i < kComponentCount; ++i) {
    const ComponentInfo& c = info(component_at(i));
    if (!c.position_dependent) e(i) = sources_[static_cast<std::size_t>(i)].value(q[c.axis]);
  }
  for (const Axis axis : kAxes) axis_errors_at(axis, q[axis], e);
}

void MachineModel::axis_errors_at(Axis axis, double position, ErrorVector& e) const noexcept {
  const AxisComponents& components = varying_on_[static_cast<std::size_t>(axis)];
  const auto source = [this](int i) -> const ErrorSource& { return sources_[static_cast<std::size_t>(i)]; };
  for (const auto& group : components.shared_knots) {
    const CubicSpline::Location where = source(group.front()).spline()->locate(position);
    for (const int i : group) e(i) = source(i).value_at(where);
  }
  for (const int i : components.others) e(i) = source(i).value(position);
}

void MachineModel::error_rates_at(const AxisPose& q, ErrorVector& de) const noexcept {
  for (int i = 0; i < kComponentCount; ++i) {
    const ErrorSource& s = sources_[static_cast<std::size_t>(i)];
    de(i) = s.rate(q[info(s.id()).axis]);
  }
}

} // namespace geartopo::machine
