// geartopo diagnosis — what the wheel families share (effect_columns.hpp).
#include "effect_columns.hpp"

#include "geartopo/effects/registry.hpp"

namespace geartopo::diagnosis::families {

Eigen::MatrixXd effect_columns(const scene::EffectSpec& spec, const std::vector<int>& fitted, const ContactStates& states) {
  Eigen::MatrixXd X(static_cast<Eigen::Index>(states.size()), static_cast<Eigen::Index>(fitted.size()));
  for (size_t j = 0; j < fitted.size(); ++j) {
    std::vector<double> values = spec.values;
    for (const int k : fitted) values[static_cast<size_t>(k)] = 0.0;
    values[static_cast<size_t>(fitted[j])] = 1.0;
    const auto e = effects::make_effect(spec.type, values, states.setup());
    X.col(static_cast<Eigen::Index>(j)) = states.deviation_um({e.get()});
  }
  return X;
}

std::string side_word(Flank side) { return side == Flank::Left ? "left" : "right"; }

std::optional<Decision> implausible(const std::string& effect, int parameter, double v, double sd) {
  const auto specs = effects::make_effect(effect)->parameters();
  const auto& spec = specs[static_cast<size_t>(parameter)];
  if (!(v - 2.0 * sd > spec.plausible_hi || v + 2.0 * sd < spec.plausible_lo)) return std::nullopt;
  return Decision{Reason::implausible_value, effect + "." + spec.key, {},
                  {{"value", v}, {"sd", sd}, {"plausible_lo", spec.plausible_lo}, {"plausible_hi", spec.plausible_hi},
                   {"at_end_of_range", 0.0}}};
}

} // namespace geartopo::diagnosis::families
