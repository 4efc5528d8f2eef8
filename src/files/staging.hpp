// Internal: the staging of the open OutputFolder (output_folder.hpp) as the writers (atomic_write.cpp) see it: a
// write below the folder goes to the same relative path in its staging folder, and is recorded. One folder per
// process, guarded by a mutex (writers run on several threads: the report's figures).
#pragma once

#include <filesystem>
#include <set>
#include <string>

namespace geartopo::output::detail {

/// Redirects writes below `dir` (absolute, normal) into `stage` (a folder inside `dir`). `replaceable` holds the
/// relative paths geartopo may replace (the manifest); any other existing file below `dir` is refused. Throws
/// OutputError when another folder is being staged.
void begin_staging(const std::filesystem::path& dir, const std::filesystem::path& stage,
                   std::set<std::filesystem::path> replaceable);
/// Ends the redirection; returns the relative paths staged since begin_staging().
std::set<std::filesystem::path> end_staging();

/// Where `file` is written: its staged copy when it lies in the folder being staged (whose parent folders are then
/// made), else `file`. While a folder is staged (a command runs), refuses an input of the run and a file in that
/// folder that geartopo did not write.
std::filesystem::path destination_for(const std::filesystem::path& file);
/// Records that `file` was written to `staged` (nothing when they are the same: not staged).
void record_staged(const std::filesystem::path& file, const std::filesystem::path& staged);

/// The reason given when a run would replace a file below `dir` that is not in the manifest.
std::string foreign_file_reason(const std::filesystem::path& dir);

} // namespace geartopo::output::detail
