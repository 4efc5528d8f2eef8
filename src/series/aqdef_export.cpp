// ISO 1328-1 values as AQDEF characteristics (aqdef_export.hpp).
#include "geartopo/series/aqdef_export.hpp"

#include "geartopo/evaluation/tolerances.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <map>
#include <tuple>

namespace geartopo::series {
namespace {

using evaluation::Quantity;

struct Item {
  Quantity quantity;
  const char* code;        // ASCII: quality systems read Windows-1252 as often as UTF-8
  const char* description;
  bool profile;
  double evaluation::TraceDeviations::*member;
  bool signed_limits;
};

const std::vector<Item>& items() {
  using T = evaluation::TraceDeviations;
  static const std::vector<Item> list{
      {Quantity::ProfileTotal, "Fa", "F_alpha total profile deviation", true, &T::total_um, false},
      {Quantity::ProfileForm, "ffa", "f_f_alpha profile form deviation", true, &T::form_um, false},
      {Quantity::ProfileSlope, "fHa", "f_H_alpha profile slope deviation", true, &T::slope_um, true},
      {Quantity::HelixTotal, "Fb", "F_beta total helix deviation", false, &T::total_um, false},
      {Quantity::HelixForm, "ffb", "f_f_beta helix form deviation", false, &T::form_um, false},
      {Quantity::HelixSlope, "fHb", "f_H_beta helix slope deviation", false, &T::slope_um, true}};
  return list;
}

} // namespace

namespace {

/// A whole-gear value (pitch, runout): its code, description, quantity and where it is read.
struct GearItem {
  Quantity quantity;
  const char* code;
  const char* description;
  std::function<std::optional<double>(const evaluation::GearEvaluation&)> value;
};

const std::vector<GearItem>& gear_items() {
  using E = evaluation::GearEvaluation;
  const auto pitch = [](bool left, bool single) {
    return [left, single](const E& e) -> std::optional<double> {
      const auto& p = left ? e.pitch_left : e.pitch_right;
      if (!p) return std::nullopt;
      return single ? p->f_p_um : p->F_p_um;
    };
  };
  static const std::vector<GearItem> list{
      {Quantity::SinglePitch, "fp_L", "f_p single pitch deviation, left flanks", pitch(true, true)},
      {Quantity::CumulativePitch, "Fp_L", "F_p total cumulative pitch deviation, left flanks", pitch(true, false)},
      {Quantity::SinglePitch, "fp_R", "f_p single pitch deviation, right flanks", pitch(false, true)},
      {Quantity::CumulativePitch, "Fp_R", "F_p total cumulative pitch deviation, right flanks", pitch(false, false)},
      {Quantity::Runout, "Fr", "F_r runout",
       [](const E& e) { return e.runout ? std::optional<double>(e.runout->F_r_um) : std::nullopt; }}};
  return list;
}

aqdef::Characteristic characteristic(std::string code, std::string description, Quantity q, bool signed_limits,
                                     const evaluation::GearParameters& parameters, std::optional<int> drawing_class) {
  aqdef::Characteristic c;
  c.code = std::move(code);
  c.description = std::move(description);
  c.nominal = 0.0;
  c.unit = "um";
  if (drawing_class) {
    const double t = evaluation::tolerance_um(q, parameters, *drawing_class);
    c.upper_limit = t;
    if (signed_limits) c.lower_limit = -t;
  }
  return c;
}

aqdef::Value value_of(double v, const AqdefGear& g, const AqdefHeader& header) {
  aqdef::Value x;
  x.value = v;
  if (g.time_epoch_s) x.time = aqdef::format_time(*g.time_epoch_s);
  x.batch = header.batch;
  x.part_ident = g.id;
  return x;
}

/// Appends the pitch and runout characteristics any gear has, with each gear's values.
void add_gear_items(aqdef::Part& part, const std::vector<AqdefGear>& gears, const evaluation::GearParameters& parameters,
                    std::optional<int> drawing_class, const AqdefHeader& header) {
  for (const auto& it : gear_items()) {
    const bool any = std::any_of(gears.begin(), gears.end(), [&](const AqdefGear& g) { return it.value(*g.evaluation).has_value(); });
    if (!any) continue;
    auto c = characteristic(it.code, fmt::format("{} (ISO 1328-1)", it.description), it.quantity, false, parameters, drawing_class);
    for (const auto& g : gears)
      if (const auto v = it.value(*g.evaluation)) c.values.push_back(value_of(*v, g, header));
    part.characteristics.push_back(std::move(c));
  }
}

} // namespace

aqdef::Part iso_aqdef(const std::vector<AqdefGear>& gears, const evaluation::GearParameters& parameters,
                      std::optional<int> drawing_class, const AqdefHeader& header) {
  aqdef::Part part;
  part.number = header.part_number;
  part.description = header.part_description;
  part.machine = header.machine;
  // (tooth, side, item) → characteristic index, in the order of the key.
  std::map<std::tuple<int, int, size_t>, size_t> index;
  for (const auto& g : gears)
    for (const auto& f : g.evaluation->flanks)
      for (size_t i = 0; i < items().size(); ++i) index.emplace(std::make_tuple(f.tooth, f.side == Flank::Left ? 0 : 1, i), 0);
  for (auto& [key, at] : index) {
    const auto& [tooth, side, i] = key;
    const Item& it = items()[i];
    at = part.characteristics.size();
    part.characteristics.push_back(characteristic(
        fmt::format("{}_T{:02}_{}", it.code, tooth, side == 0 ? "L" : "R"),
        fmt::format("{}, tooth {}, {} flank (ISO 1328-1)", it.description, tooth, side == 0 ? "left" : "right"),
        it.quantity, it.signed_limits, parameters, drawing_class));
  }
  for (const auto& g : gears)
    for (const auto& f : g.evaluation->flanks)
      for (size_t i = 0; i < items().size(); ++i) {
        const Item& it = items()[i];
        const auto& trace = it.profile ? f.profile : f.helix;
        part.characteristics[index.at(std::make_tuple(f.tooth, f.side == Flank::Left ? 0 : 1, i))].values.push_back(
            value_of(trace.*(it.member), g, header));
      }
  add_gear_items(part, gears, parameters, drawing_class, header);
  return part;
}

} // namespace geartopo::series
