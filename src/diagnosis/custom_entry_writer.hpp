// geartopo diagnosis, private — the fitted values of one of the user's own effects written back into its entry of
// the scene's `custom_effects` (scene_writer.hpp), keeping every other line of the text as it was.
#pragma once

#include <string>
#include <vector>

namespace geartopo::diagnosis {

/// `text` with the entry named `name` of its top-level `custom_effects` list carrying `values` (parameter keys `keys`,
/// file units) as each parameter's `value`, and the entry's `uncertainty` map and `correlation` list replaced by
/// `uncertainties` (> 0 only) and `pairs` ("[key_a, key_b, r]"). Throws std::runtime_error when the entry or a
/// parameter's value is not found in a form it can rewrite (block or one-line flow maps).
std::string with_custom_entry_values(const std::string& text, const std::string& name, const std::vector<std::string>& keys,
                                     const std::vector<double>& values, const std::vector<double>& uncertainties,
                                     const std::vector<std::string>& pairs, const std::string& comment);

} // namespace geartopo::diagnosis
