// geartopo — the machine's profile and helix values beside geartopo's evaluation (machine_flank_values.hpp). Units: µm,
// mm.
#include "geartopo/workbench/machine_flank_values.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <stdexcept>

namespace geartopo::workbench {
namespace {

using measurement::MachineQuantity;
using Values = std::array<double, 6>; // in the order of MachineQuantity

std::size_t index(MachineQuantity q) { return static_cast<std::size_t>(q); }
bool is_helix(MachineQuantity q) { return index(q) >= 3; }
bool is_slope(MachineQuantity q) { return q == MachineQuantity::ProfileSlope || q == MachineQuantity::HelixSlope; }

Values values_of(const evaluation::FlankEvaluation& f) {
  return {f.profile.slope_um, f.profile.form_um, f.profile.total_um, f.helix.slope_um, f.helix.form_um, f.helix.total_um};
}

/// The flank's traces evaluated over other ranges (ξ0 … ξ1 roll length, z0 … z1), reported as evaluate_gear reports
/// (gear_evaluation.cpp: × the direction factor, f_Hβ × the helix sign factor). nullopt when a trace does not cover
/// its range.
std::optional<Values> evaluate_over(const grinding::FlankTopology& ft, double xi0, double xi1, double z0, double z1,
                                    const evaluation::IsoConventions& c) {
  evaluation::Trace p, h;
  for (const auto& q : ft.profile) p.position_mm.push_back(q.roll_length_mm), p.deviation_um.push_back(q.deviation_um);
  for (const auto& q : ft.helix) h.position_mm.push_back(q.z_mm), h.deviation_um.push_back(q.deviation_um);
  p.range_start_mm = xi0, p.range_end_mm = xi1, h.range_start_mm = z0, h.range_end_mm = z1;
  try {
    const auto a = evaluation::evaluate_trace(p), b = evaluation::evaluate_trace(h);
    const double k = evaluation::reported_per_normal(c);
    return Values{k * a.slope_um, k * a.form_um, k * a.total_um,
                  k * b.slope_um * evaluation::helix_slope_factor(c, ft.flank), k * b.form_um, k * b.total_um};
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
}

// A range of the export for a flank: one value serves both, two are left and right (as the curve reader reads them).
std::optional<double> export_range(const measurement::KlingelnbergFile* f, const char* symbol, Flank side) {
  if (!f) return std::nullopt;
  const auto it = f->ranges.find(symbol);
  if (it == f->ranges.end() || it->second.values.empty()) return std::nullopt;
  const auto& v = it->second.values;
  return side == Flank::Right && v.size() >= 2 ? v[1] : v[0];
}

std::string setting(const measurement::KlingelnbergValues& m, int code) {
  const auto it = m.settings.find(code);
  return it == m.settings.end() ? std::string() : fmt::format("header line {} '{}'", code, it->second.text);
}

/// What the comparison reads: the machine's values, the gear, geartopo's traces and their evaluation, the export.
struct Inputs {
  const measurement::KlingelnbergValues& machine;
  const gears::GearGeometry& g;
  const gears::EvaluationRanges& r;
  const std::vector<grinding::FlankTopology>& traces;
  const evaluation::GearEvaluation& evaluation;
  const measurement::KlingelnbergFile* curves;
};

struct FlankData {
  const grinding::FlankTopology* trace = nullptr;
  const evaluation::FlankEvaluation* eval = nullptr;
};

FlankData flank_data(const Inputs& in, int tooth, Flank side) {
  FlankData f;
  for (const auto& t : in.traces)
    if (t.tooth == tooth && t.flank == side) f.trace = &t;
  for (const auto& e : in.evaluation.flanks)
    if (e.tooth == tooth && e.side == side) f.eval = &e;
  return f;
}

/// One row per value the machine wrote for a tooth's flank that geartopo evaluated; the others in `not_compared`.
void compare_rows(const Inputs& in, MachineFlankComparison& c) {
  for (const auto& v : in.machine.flank_values) {
    if (v.statistic != measurement::MachineStatistic::Tooth || !v.quantity) continue; // statistics, second positions
    const std::string what = fmt::format("{} tooth {} {} (line {})", measurement::symbol(*v.quantity), v.tooth,
                                         to_string(v.flank), v.line);
    const auto f = flank_data(in, v.tooth, v.flank);
    if (!f.trace || !f.eval) {
      c.not_compared.push_back(what + ": geartopo did not evaluate this flank (no profile and helix trace of it)");
      continue;
    }
    if (!v.value_um) {
      c.not_compared.push_back(what + ": the machine wrote no value (placeholder)");
      continue;
    }
    MachineFlankRow row;
    row.tooth = v.tooth;
    row.side = v.flank;
    row.quantity = *v.quantity;
    row.machine_um = *v.value_um;
    row.geartopo_um = values_of(*f.eval)[index(*v.quantity)];
    row.trace_position_mm = is_helix(*v.quantity) ? f.trace->helix.front().diameter_mm : f.trace->profile.front().z_mm;
    row.flagged = std::abs(row.machine_um - row.geartopo_um) > kMachineMismatchUm;
    row.line = v.line;
    c.flagged += row.flagged;
    c.rows.push_back(row);
  }
}

/// geartopo's value of `row` evaluated over the export's evaluation range (d1 … d2, b1 … b2) or over the whole
/// measured trace; nullopt when the export does not give the range or a trace does not cover it.
std::optional<double> evaluated_over(const Inputs& in, const MachineFlankRow& row, bool export_ranges) {
  const auto* t = flank_data(in, row.tooth, row.side).trace;
  double xi0 = t->profile.front().roll_length_mm, xi1 = t->profile.back().roll_length_mm;
  double z0 = t->helix.front().z_mm, z1 = t->helix.back().z_mm;
  if (export_ranges) {
    const auto d1 = export_range(in.curves, "d1", row.side), d2 = export_range(in.curves, "d2", row.side);
    const auto b1 = export_range(in.curves, "b1", row.side), b2 = export_range(in.curves, "b2", row.side);
    if (is_helix(row.quantity) ? !(b1 && b2) : !(d1 && d2)) return std::nullopt;
    if (d1 && d2 && *d1 >= in.g.base_diameter_mm() && *d2 >= in.g.base_diameter_mm())
      xi0 = in.g.roll_length_at(*d1), xi1 = in.g.roll_length_at(*d2);
    if (b1 && b2) z0 = *b1, z1 = *b2;
  }
  const auto v = evaluate_over(*t, xi0, xi1, z0, z1, in.evaluation.conventions);
  return v ? std::optional<double>((*v)[index(row.quantity)]) : std::nullopt;
}

/// Another reading of the machine's value: the cause it would be, whether it applies to the quantity, geartopo's
/// value under it, and its words.
struct Reading {
  MachineCause cause;
  bool applies;
  std::function<std::optional<double>(const MachineFlankRow&)> value;
  std::string words;
};

std::vector<Reading> readings_of(const Inputs& in, MachineQuantity q) {
  const auto& conv = in.evaluation.conventions;
  const double cos_bb = std::cos(conv.base_helix_angle_rad), b = in.g.spec().face_width_mm;
  const double L_beta = in.r.helix_evaluation_length();
  const bool transverse = conv.direction == evaluation::IsoDirection::Transverse;
  const std::string ranges_text = fmt::format("L_α = ξ {:.3f} … {:.3f} mm, L_β = z {:.3f} … {:.3f} mm (the scene's)",
                                              in.r.xi_eval_start_mm, in.r.xi_eval_end_mm, in.r.z_eval_start_mm,
                                              in.r.z_eval_end_mm);
  const std::string sign_settings =
      is_helix(q) ? fmt::format(" ({})", setting(in.machine, 178).empty() ? "the export states no sign setting"
                                                                           : setting(in.machine, 178))
                  : "";
  const std::string face_setting = setting(in.machine, 179);
  return {
      {MachineCause::OppositeSign, is_slope(q), [](const MachineFlankRow& row) { return std::optional(-row.geartopo_um); },
       fmt::format("the machine's {} has the opposite sign{}", measurement::symbol(q), sign_settings)},
      {MachineCause::Direction, cos_bb < 1.0,
       [=](const MachineFlankRow& row) { return std::optional(row.geartopo_um * (transverse ? cos_bb : 1.0 / cos_bb)); },
       fmt::format("the machine reports {} {} (geartopo: {}; factor {} = {:.4f})", measurement::symbol(q),
                   transverse ? "along the flank normal" : "in the transverse plane", transverse ? "transverse" : "normal",
                   transverse ? "cos β_b" : "1/cos β_b", transverse ? cos_bb : 1.0 / cos_bb)},
      {MachineCause::FaceWidth, q == MachineQuantity::HelixSlope,
       [=](const MachineFlankRow& row) { return std::optional(row.geartopo_um * b / L_beta); },
       fmt::format("the machine refers f_Hβ to the face width b = {:.3f} mm, geartopo to L_β = {:.3f} mm as ISO 1328-1 "
                   "does (factor b/L_β = {:.4f}); {}",
                   b, L_beta, b / L_beta,
                   face_setting.empty() ? std::string("the export does not state it (no header line 179)")
                                        : face_setting + (in.machine.helix_slope_referred_to_face_width() ? " says so"
                                                                                                          : " does not say so"))},
      {MachineCause::EvaluationRange, in.curves != nullptr,
       [&in](const MachineFlankRow& row) { return evaluated_over(in, row, true); },
       fmt::format("the machine evaluates over the export's evaluation range (header d1 … d2, b1 … b2), geartopo over {}",
                   ranges_text)},
      {MachineCause::MeasuringRange, true, [&in](const MachineFlankRow& row) { return evaluated_over(in, row, false); },
       fmt::format("the machine evaluates the whole measured trace, geartopo over {}", ranges_text)},
  };
}

/// A filter removes short waves: the slope stays, form and total both shrink. Not evaluated (the machine's filter is
/// not known), so named only when every flagged flank of form or total quantity `q` shows exactly that.
bool filter_explains(const MachineFlankComparison& c, MachineQuantity q, const std::vector<const MachineFlankRow*>& rows) {
  const auto sibling = [&](MachineQuantity a) {
    if (a == MachineQuantity::ProfileForm) return MachineQuantity::ProfileTotal;
    if (a == MachineQuantity::ProfileTotal) return MachineQuantity::ProfileForm;
    if (a == MachineQuantity::HelixForm) return MachineQuantity::HelixTotal;
    return MachineQuantity::HelixForm;
  };
  const MachineQuantity slope = is_helix(q) ? MachineQuantity::HelixSlope : MachineQuantity::ProfileSlope;
  const auto find = [&](int tooth, Flank side, MachineQuantity k) -> const MachineFlankRow* {
    for (const auto& row : c.rows)
      if (row.tooth == tooth && row.side == side && row.quantity == k) return &row;
    return nullptr;
  };
  bool filter = true;
  for (const auto* row : rows) {
    if (!row->flagged) continue;
    const auto* other = find(row->tooth, row->side, sibling(q));
    const auto* sl = find(row->tooth, row->side, slope);
    filter = filter && row->machine_um < row->geartopo_um && other && other->flagged &&
             other->machine_um < other->geartopo_um && sl && !sl->flagged;
  }
  return filter;
}

/// Quantity `q`'s rows under each other reading: a reading is the likely cause when it makes every row agree.
/// nullopt when the machine wrote no value of `q`.
std::optional<MachineQuantitySummary> summarise(const Inputs& in, const MachineFlankComparison& c, MachineQuantity q) {
  MachineQuantitySummary s;
  s.quantity = q;
  std::vector<const MachineFlankRow*> rows;
  for (const auto& row : c.rows)
    if (row.quantity == q) {
      rows.push_back(&row);
      s.flagged += row.flagged;
      s.max_abs_difference_um = std::max(s.max_abs_difference_um, std::abs(row.machine_um - row.geartopo_um));
    }
  s.rows = rows.size();
  if (rows.empty()) return std::nullopt;
  if (s.flagged == 0) return s;
  s.cause = MachineCause::Unexplained;
  for (const auto& reading : readings_of(in, q)) {
    if (!reading.applies) continue;
    bool all = true;
    for (const auto* row : rows) {
      const auto v = reading.value(*row);
      all = all && v && std::abs(row->machine_um - *v) <= kMachineMismatchUm;
    }
    if (!all) continue;
    // Readings that give the same values cannot be told apart by the numbers (f_Hβ referred to b equals f_Hβ of the
    // whole trace when L_β is centred on the face width): the first is the cause, the others are named with it.
    if (s.cause == MachineCause::Unexplained) {
      s.cause = reading.cause;
      s.likely_cause = reading.words;
    } else {
      s.likely_cause += "; or equally: " + reading.words;
    }
  }
  if (s.cause == MachineCause::Unexplained && !is_slope(q) && filter_explains(c, q, rows)) {
    s.cause = MachineCause::Filter;
    s.likely_cause = fmt::format("the slope agrees but form and total are both smaller on every flagged flank: "
                                 "consistent with the machine's filter ({}), which geartopo does not apply",
                                 in.machine.filters.empty() ? std::string("the export names none")
                                                            : fmt::format("{}", fmt::join(in.machine.filters, "; ")));
  }
  if (s.cause == MachineCause::Unexplained)
    s.likely_cause = "no other sign, direction, reference length or range makes every value agree: the machine "
                     "evaluated other traces, with a filter, or the values differ";
  return s;
}

} // namespace

const char* to_string(MachineCause c) {
  switch (c) {
  case MachineCause::None: return "";
  case MachineCause::OppositeSign: return "opposite-sign";
  case MachineCause::Direction: return "direction";
  case MachineCause::FaceWidth: return "face-width";
  case MachineCause::EvaluationRange: return "evaluation-range";
  case MachineCause::MeasuringRange: return "measuring-range";
  case MachineCause::Filter: return "filter";
  case MachineCause::Unexplained: return "unexplained";
  }
  return "";
}

MachineFlankComparison compare_machine_flank_values(const measurement::KlingelnbergValues& machine,
                                                    const gears::GearGeometry& g, const gears::EvaluationRanges& r,
                                                    const std::vector<grinding::FlankTopology>& traces,
                                                    const evaluation::GearEvaluation& evaluation,
                                                    const measurement::KlingelnbergFile* curves) {
  const Inputs in{machine, g, r, traces, evaluation, curves};
  MachineFlankComparison c;
  compare_rows(in, c);
  for (const auto q : measurement::kMachineQuantities)
    if (auto s = summarise(in, c, q)) c.quantities.push_back(std::move(*s));
  return c;
}

} // namespace geartopo::workbench
