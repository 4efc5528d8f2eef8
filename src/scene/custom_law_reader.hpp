// geartopo scene, private — one item of a scene's `custom_effects` (docs/scene-format.md): the user's law read
// strictly, compiled, and registered by name (effects/custom_effect.hpp).
#pragma once

#include "yaml_reader.hpp"

#include "geartopo/effects/custom_effect.hpp"

#include <memory>

namespace geartopo::scene {

/// Reads name, parameters ({value, min, max, unit} each), deviation_um and dressing_interval_strokes from `m` (its
/// other keys are the caller's); throws InputError located at the field, and for an expression at the character of
/// the expression at fault (line and column in the file when the expression stands on one line).
std::shared_ptr<const effects::CustomLaw> read_custom_law(MapReader& m, const Scene& scene);

} // namespace geartopo::scene
