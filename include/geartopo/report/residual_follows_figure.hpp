// geartopo — the figure of what the residual follows (docs/diagnosis.md, "What the residual follows"): the residual
// with the set-up terms removed against each process variable, one panel each, left and right flanks apart, with the
// fitted dependence drawn over it. Units: µm against each variable's own unit.
#pragma once

#include "geartopo/diagnosis/residual_follows.hpp"
#include "geartopo/measurement/measured_points.hpp"

#include <filesystem>
#include <vector>

namespace geartopo::report {

/// Writes `png` (panels in `panel_dir`), one panel per variable of `follows`, strongest first. Throws
/// std::runtime_error when rendering or writing fails, std::invalid_argument when `follows` has no variable.
void render_residual_follows(const diagnosis::ResidualFollows& follows,
                             const std::vector<measurement::MeasuredPoint>& points, const std::filesystem::path& png,
                             const std::filesystem::path& panel_dir);

} // namespace geartopo::report
