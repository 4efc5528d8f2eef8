// geartopo — the gear's geometry as a readable table or as one JSON object (keys carry units: _mm, _deg).
#pragma once

#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/scene/scene.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace geartopo::report {

nlohmann::json gear_json(const scene::Scene& scene, const gears::GearGeometry& g);
std::string gear_table(const scene::Scene& scene, const gears::GearGeometry& g);

} // namespace geartopo::report
