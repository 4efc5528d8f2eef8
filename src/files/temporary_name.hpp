// Internal: the name of a writer's temporary, ".gt-PID-N.ext" (is_geartopo_temporary, output_folder.hpp, reads it).
#pragma once

#include <filesystem>

namespace geartopo::output::detail {

/// "<folder>/.gt-<pid>-<n><ext>": hidden, unique per process and call, same extension as the final name, and short
/// (at most 41 bytes), so that a final name of NAME_MAX bytes still has a temporary.
std::filesystem::path temporary_for(const std::filesystem::path& file);

} // namespace geartopo::output::detail
