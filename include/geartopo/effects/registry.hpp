// geartopo — the effect registry: names of every effect in the library and a factory.
#pragma once

#include "geartopo/effects/effect.hpp"

#include <memory>
#include <string>
#include <vector>

namespace geartopo::effects {

/// Every registered effect type, in library order.
const std::vector<std::string>& effect_types();
/// A new effect of this type with default parameters: a library effect, or a custom law registered in this process
/// (custom_effect.hpp, from a scene's custom_effects); nullptr if the type is unknown.
std::unique_ptr<Effect> make_effect(std::string_view type);
/// A new effect of a known type with these values (file units, parameter order), bound to the set-up.
/// Throws std::invalid_argument for an unknown type or a wrong number of values.
std::unique_ptr<Effect> make_effect(std::string_view type, std::vector<double> values, const grinding::GrindingSetup& setup);

/// True for a registered custom law's name (custom_effect.hpp), false for a library effect or an unknown name.
bool is_custom_effect(std::string_view type);

} // namespace geartopo::effects
