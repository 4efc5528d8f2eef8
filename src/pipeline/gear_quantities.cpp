// The quantities a Monte Carlo sample records of a gear (gear_quantities, monte_carlo.hpp), their names and what
// each can physically be (quantity_names.hpp).
#include "geartopo/pipeline/monte_carlo.hpp"

#include "quantity_names.hpp"

#include "geartopo/core/text_field.hpp"
#include "geartopo/evaluation/tolerances.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <map>

namespace geartopo::pipeline {

namespace detail {

namespace {

constexpr evaluation::Quantity kAllQuantities[] = {
    evaluation::Quantity::SinglePitch, evaluation::Quantity::CumulativePitch, evaluation::Quantity::ProfileSlope,
    evaluation::Quantity::ProfileForm,  evaluation::Quantity::ProfileTotal,    evaluation::Quantity::HelixSlope,
    evaluation::Quantity::HelixForm,    evaluation::Quantity::HelixTotal,      evaluation::Quantity::Runout};

} // namespace

std::string_view ascii_name(evaluation::Quantity q) {
  using evaluation::Quantity;
  switch (q) {
  case Quantity::SinglePitch: return "f_p";
  case Quantity::CumulativePitch: return "F_p";
  case Quantity::ProfileSlope: return "f_Halpha";
  case Quantity::ProfileForm: return "f_falpha";
  case Quantity::ProfileTotal: return "F_alpha";
  case Quantity::HelixSlope: return "f_Hbeta";
  case Quantity::HelixForm: return "f_fbeta";
  case Quantity::HelixTotal: return "F_beta";
  case Quantity::Runout: return "F_r";
  }
  return "?";
}

std::string QuantityRule::refusal(double v) const {
  switch (kind) {
  case Kind::IsoClass:
    if (v != std::floor(v) || v < evaluation::kFinestClass || v > evaluation::kWorseThanClass11)
      return fmt::format("is not a class of ISO 1328-1: a whole number of {} … {} ({}: worse than class {})",
                         evaluation::kFinestClass, evaluation::kCoarsestClass, evaluation::kWorseThanClass11,
                         evaluation::kCoarsestClass);
    return {};
  case Kind::Magnitude:
    if (v < 0.0) return "µm is negative: an ISO deviation or largest |deviation| is a magnitude, ≥ 0";
    [[fallthrough]];
  case Kind::Signed:
    if (std::abs(v) > kMaxQuantityUm)
      return fmt::format("µm is beyond ±{} µm, more than a ground gear deviates (a wrong unit or an edited file)",
                         kMaxQuantityUm);
    return {};
  }
  return {};
}

std::optional<QuantityRule> rule_of(const std::string& name) {
  using K = QuantityRule::Kind;
  if (name == "overall_class") return QuantityRule{K::IsoClass};
  if (name == "largest_abs_um") return QuantityRule{K::Magnitude};
  if (name == "thickness_um" || name == "rotation_um") return QuantityRule{K::Signed};
  for (const auto q : kAllQuantities) {
    if (name == fmt::format("{}_um", ascii_name(q))) return QuantityRule{K::Magnitude}; // |worst value| (gear_quantities)
    if (name == fmt::format("{}_class", ascii_name(q))) return QuantityRule{K::IsoClass};
  }
  return std::nullopt;
}

std::vector<std::string> known_quantity_names() {
  std::vector<std::string> out;
  for (const auto q : kAllQuantities) {
    out.push_back(fmt::format("{}_um", ascii_name(q)));
    out.push_back(fmt::format("{}_class", ascii_name(q)));
  }
  for (const char* n : {"overall_class", "largest_abs_um", "thickness_um", "rotation_um"}) out.emplace_back(n);
  return out;
}

} // namespace detail

GearQuantities gear_quantities(const workbench::IsoResult& iso, const std::vector<grinding::FlankTopology>& topo) {
  GearQuantities g;
  const auto add = [&g](std::string name, double v) {
    g.names.push_back(std::move(name));
    g.values.push_back(v);
  };
  const auto& c = iso.evaluation.classification;
  for (const auto& q : c.quantities) {
    // |value|: the worst slope's sign flips with the flank that is worst, which would split one band in two; the
    // class is judged by |value| too (evaluation/gear_evaluation.hpp, QuantityClass).
    add(fmt::format("{}_um", detail::ascii_name(q.quantity)), std::abs(q.worst_value_um));
    if (q.flank_class) add(fmt::format("{}_class", detail::ascii_name(q.quantity)), *q.flank_class);
  }
  if (c.overall) add("overall_class", *c.overall);
  add("largest_abs_um", grinding::largest_abs_deviation_um(topo));
  std::map<int, std::pair<double, double>> mean_by_tooth; // tooth → (left, right) mean grid deviation
  std::map<int, int> sides;
  for (const auto& ft : topo) {
    if (ft.grid.empty()) continue;
    double sum = 0.0;
    for (const auto& p : ft.grid) sum += p.deviation_um;
    auto& m = mean_by_tooth[ft.tooth];
    (ft.flank == Flank::Left ? m.first : m.second) = sum / static_cast<double>(ft.grid.size());
    ++sides[ft.tooth];
  }
  double thickness = 0.0, rotation = 0.0;
  int teeth = 0;
  for (const auto& [tooth, m] : mean_by_tooth) {
    if (sides[tooth] != 2) continue;
    thickness += m.first + m.second;
    rotation += 0.5 * (m.first - m.second);
    ++teeth;
  }
  if (teeth > 0) {
    add("thickness_um", thickness / teeth);
    add("rotation_um", rotation / teeth);
  }
  return g;
}

std::optional<std::string> quantity_value_refusal(const std::string& name, double value) {
  const auto rule = detail::rule_of(name);
  if (!rule)
    return fmt::format("'{}' is not a quantity geartopo writes ({})", text::excerpt(name), fmt::join(detail::known_quantity_names(), ", "));
  if (!std::isfinite(value)) return fmt::format("{} is not a finite number", value);
  if (const std::string why = rule->refusal(value); !why.empty()) return fmt::format("{:.6g} {}", value, why);
  return std::nullopt;
}

} // namespace geartopo::pipeline
