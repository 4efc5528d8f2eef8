// geartopo — the effect registry: names of every effect in the library and a factory.
#pragma once

#include "geartopo/effects/effect.hpp"

#include <memory>
#include <string>
#include <vector>

namespace geartopo::effects {

/// Every registered effect type, in library order.
const std::vector<std::string>& effect_types();
/// A new effect of this type with default parameters; nullptr if the type is unknown.
std::unique_ptr<Effect> make_effect(std::string_view type);
/// A new effect of a known type with these values (file units, parameter order), bound to the set-up.
/// Throws std::invalid_argument for an unknown type or a wrong number of values.
std::unique_ptr<Effect> make_effect(std::string_view type, std::vector<double> values, const grinding::GrindingSetup& setup);

} // namespace geartopo::effects
