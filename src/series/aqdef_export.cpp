// ISO 1328-1 values as AQDEF characteristics (aqdef_export.hpp).
#include "geartopo/series/aqdef_export.hpp"

#include "geartopo/evaluation/tolerances.hpp"

#include <fmt/format.h>

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
    aqdef::Characteristic c;
    c.code = fmt::format("{}_T{:02}_{}", it.code, tooth, side == 0 ? "L" : "R");
    c.description = fmt::format("{}, tooth {}, {} flank (ISO 1328-1)", it.description, tooth, side == 0 ? "left" : "right");
    c.nominal = 0.0;
    c.unit = "um";
    if (drawing_class) {
      const double t = evaluation::tolerance_um(it.quantity, parameters, *drawing_class);
      c.upper_limit = t;
      if (it.signed_limits) c.lower_limit = -t;
    }
    at = part.characteristics.size();
    part.characteristics.push_back(std::move(c));
  }
  for (const auto& g : gears)
    for (const auto& f : g.evaluation->flanks)
      for (size_t i = 0; i < items().size(); ++i) {
        const Item& it = items()[i];
        const auto& trace = it.profile ? f.profile : f.helix;
        aqdef::Value v;
        v.value = trace.*(it.member);
        if (g.time_epoch_s) v.time = aqdef::format_time(*g.time_epoch_s);
        v.batch = header.batch;
        part.characteristics[index.at(std::make_tuple(f.tooth, f.side == Flank::Left ? 0 : 1, i))].values.push_back(v);
      }
  return part;
}

} // namespace geartopo::series
