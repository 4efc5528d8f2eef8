// geartopo — error component changes and their laws (component_change.hpp). Units: mm, rad, s inside.
#include "geartopo/machine/component_change.hpp"

#include "geartopo/machine/kinematic_chain.hpp"

#include <fmt/format.h>

#include <cmath>

namespace geartopo::machine {

std::string_view to_string(ChangeLaw law) {
  switch (law) {
  case ChangeLaw::Constant: return "constant";
  case ChangeLaw::LinearInTime: return "linear_in_time";
  case ChangeLaw::SteadyState: return "steady_state";
  case ChangeLaw::PerRevolution: return "per_revolution";
  }
  return "constant";
}

std::string law_name(ChangeLaw law, int order) {
  if (law != ChangeLaw::PerRevolution) return std::string(to_string(law));
  if (order == 1) return "once_per_revolution";
  if (order == 2) return "twice_per_revolution";
  return fmt::format("{}_times_per_revolution", order);
}

std::optional<NamedLaw> law_from_name(std::string_view name) {
  for (ChangeLaw l : {ChangeLaw::Constant, ChangeLaw::LinearInTime, ChangeLaw::SteadyState})
    if (to_string(l) == name) return NamedLaw{l, 1};
  if (name == "once_per_revolution") return NamedLaw{ChangeLaw::PerRevolution, 1};
  if (name == "twice_per_revolution") return NamedLaw{ChangeLaw::PerRevolution, 2};
  constexpr std::string_view suffix = "_times_per_revolution";
  if (name.size() <= suffix.size() || name.substr(name.size() - suffix.size()) != suffix) return std::nullopt;
  const std::string_view digits = name.substr(0, name.size() - suffix.size());
  int k = 0;
  for (char c : digits) {
    if (c < '0' || c > '9' || k > kMaxRevolutionOrder) return std::nullopt;
    k = 10 * k + (c - '0');
  }
  // "3_times…" and up: 1 and 2 have their own words, a leading zero is no name law_name gives.
  if (k < 3 || k > kMaxRevolutionOrder || digits.front() == '0') return std::nullopt;
  return NamedLaw{ChangeLaw::PerRevolution, k};
}

double ComponentChange::law_shape(double time_s, double c_rad) const {
  switch (law) {
  case ChangeLaw::Constant: return 1.0;
  case ChangeLaw::LinearInTime: return time_s;
  case ChangeLaw::SteadyState: return -std::expm1(-time_s / time_constant_s);
  case ChangeLaw::PerRevolution: return std::cos(order * c_rad - phase_rad);
  }
  return 1.0;
}

std::string size_key(ChangeLaw law, Quantity q) {
  const std::string unit(file_unit(q));
  switch (law) {
  case ChangeLaw::Constant: return "change_" + unit;
  case ChangeLaw::LinearInTime: return "rate_" + unit + "_per_min";
  case ChangeLaw::SteadyState: return "final_" + unit;
  case ChangeLaw::PerRevolution: return "amplitude_" + unit;
  }
  return "change_" + unit;
}

double file_per_internal(ChangeLaw law, Quantity q) {
  const double unit = q == Quantity::Length ? 1e3 : 1e6; // µm per mm, µrad per rad
  return law == ChangeLaw::LinearInTime ? unit * 60.0 : unit;
}

std::string describe(const ComponentChange& c, const std::string& size_text, const std::string& phase_text,
                     const KinematicChain* chain) {
  const auto& i = info(chain, c.component);
  const std::string unit = i.quantity == Quantity::Length ? "µm" : "µrad";
  switch (c.law) {
  case ChangeLaw::Constant: return fmt::format("{} ({}) changed by {} {}", i.name, i.meaning, size_text, unit);
  case ChangeLaw::LinearInTime: return fmt::format("{} ({}) drifts by {} {}/min", i.name, i.meaning, size_text, unit);
  case ChangeLaw::SteadyState:
    return fmt::format("{} ({}) approaches {} {} with a time constant of {:.0f} s", i.name, i.meaning, size_text, unit,
                       c.time_constant_s);
  case ChangeLaw::PerRevolution: {
    const double phase_deg = c.phase_rad * 180.0 / 3.141592653589793;
    const std::string phase = phase_text.empty() ? fmt::format("{:.0f}", phase_deg) : phase_text;
    if (c.order == 1)
      return fmt::format("{} ({}) changed by {} {} once per table revolution, largest at C = {}°", i.name, i.meaning,
                         size_text, unit, phase);
    // cos(kγ − φ) is largest where kγ = φ, i.e. at γ = φ/k and every 360°/k on: the first such C in [0°, 360°/k).
    const double period_deg = 360.0 / c.order;
    const double first_largest = std::fmod(std::fmod(phase_deg / c.order, period_deg) + period_deg, period_deg);
    return fmt::format("{} ({}) changed by {} {} {} per table revolution, as cos({}·C − φ) with φ = {}° (largest at "
                       "C = {:.0f}° and every {:g}° on)",
                       i.name, i.meaning, size_text, unit, c.order == 2 ? "twice" : fmt::format("{} times", c.order),
                       c.order, phase, first_largest, period_deg);
  }
  }
  return {};
}

} // namespace geartopo::machine
