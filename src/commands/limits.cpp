// geartopo — the bounds every front end enforces (limits.hpp): core/limits.hpp's, with the argument's name.
#include "geartopo/commands/limits.hpp"

#include "geartopo/core/limits.hpp"

namespace geartopo::commands {

ArgumentError::ArgumentError(std::string argument, const std::string& expected)
    : std::invalid_argument(argument + ": " + expected), argument_(std::move(argument)) {}

namespace {

void refuse(const std::optional<std::string>& refusal, std::string_view argument) {
  if (refusal) throw ArgumentError(std::string(argument), *refusal);
}

} // namespace

void check_noise_um(double v, std::string_view argument) { refuse(limits::noise_um_refusal(v), argument); }

void check_synthetic_noise_um(double v, std::string_view argument) {
  refuse(limits::synthetic_noise_um_refusal(v), argument);
}

void check_samples(long long samples, std::string_view argument) { refuse(limits::samples_refusal(samples), argument); }

void check_grid(long long rows, long long cols, std::string_view argument) {
  refuse(limits::grid_refusal(rows, cols), argument);
}

void check_path(const std::string& path, std::string_view argument) { refuse(limits::path_refusal(path), argument); }

void check_teeth(const std::vector<int>& teeth, int z, std::string_view argument) {
  refuse(limits::teeth_refusal(teeth, z), argument);
}

} // namespace geartopo::commands
