// geartopo — error component changes and their laws (component_change.hpp). Units: mm, rad, s inside.
#include "geartopo/machine/component_change.hpp"

#include <fmt/format.h>

#include <cmath>

namespace geartopo::machine {

std::string_view to_string(ChangeLaw law) {
  switch (law) {
  case ChangeLaw::Constant: return "constant";
  case ChangeLaw::LinearInTime: return "linear_in_time";
  case ChangeLaw::SteadyState: return "steady_state";
  case ChangeLaw::OncePerRevolution: return "once_per_revolution";
  }
  return "constant";
}

std::optional<ChangeLaw> change_law_from_name(std::string_view name) {
  for (ChangeLaw l : {ChangeLaw::Constant, ChangeLaw::LinearInTime, ChangeLaw::SteadyState, ChangeLaw::OncePerRevolution})
    if (to_string(l) == name) return l;
  return std::nullopt;
}

double ComponentChange::law_shape(double time_s, double c_rad) const {
  switch (law) {
  case ChangeLaw::Constant: return 1.0;
  case ChangeLaw::LinearInTime: return time_s;
  case ChangeLaw::SteadyState: return -std::expm1(-time_s / time_constant_s);
  case ChangeLaw::OncePerRevolution: return std::cos(c_rad - phase_rad);
  }
  return 1.0;
}

std::string size_key(ChangeLaw law, Quantity q) {
  const std::string unit(file_unit(q));
  switch (law) {
  case ChangeLaw::Constant: return "change_" + unit;
  case ChangeLaw::LinearInTime: return "rate_" + unit + "_per_min";
  case ChangeLaw::SteadyState: return "final_" + unit;
  case ChangeLaw::OncePerRevolution: return "amplitude_" + unit;
  }
  return "change_" + unit;
}

double file_per_internal(ChangeLaw law, Quantity q) {
  const double unit = q == Quantity::Length ? 1e3 : 1e6; // µm per mm, µrad per rad
  return law == ChangeLaw::LinearInTime ? unit * 60.0 : unit;
}

std::string describe(const ComponentChange& c, const std::string& size_text, const std::string& phase_text) {
  const auto& i = info(c.component);
  const std::string unit = i.quantity == Quantity::Length ? "µm" : "µrad";
  switch (c.law) {
  case ChangeLaw::Constant: return fmt::format("{} ({}) changed by {} {}", i.name, i.meaning, size_text, unit);
  case ChangeLaw::LinearInTime: return fmt::format("{} ({}) drifts by {} {}/min", i.name, i.meaning, size_text, unit);
  case ChangeLaw::SteadyState:
    return fmt::format("{} ({}) approaches {} {} with a time constant of {:.0f} s", i.name, i.meaning, size_text, unit,
                       c.time_constant_s);
  case ChangeLaw::OncePerRevolution:
    return fmt::format("{} ({}) changed by {} {} once per table revolution, largest at C = {}°", i.name, i.meaning,
                       size_text, unit,
                       phase_text.empty() ? fmt::format("{:.0f}", c.phase_rad * 180.0 / 3.141592653589793) : phase_text);
  }
  return {};
}

} // namespace geartopo::machine
