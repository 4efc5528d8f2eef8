#pragma once
// Shared helpers of the render tests: output directory, standard checks, small data sets.

#include "geartopo/render/common.hpp"
#include "geartopo/render/image.hpp"

#include <filesystem>
#include <string>

namespace geartopo::render::test {

/// A fresh path in the test output directory (kept after the run for a look by eye).
std::filesystem::path output(const std::string& name);

/// The checks every rendered figure must pass: the requested size, not blank (grey-level variance and share of
/// non-white pixels above the thresholds).
void expect_figure(const std::filesystem::path& png, ImageSize size, double min_variance = 150.0,
                   double min_share = 0.03);

} // namespace geartopo::render::test
