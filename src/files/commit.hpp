// Internal: an output folder's manifest and its commit (output_folder.hpp, "Commit", "Recovery", "Manifest").
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace geartopo::output::detail {

inline constexpr const char* kStagePrefix = ".gt-stage-";
inline constexpr const char* kCommitPrefix = ".gt-commit-";

/// The relative paths a manifest lists (none when it is missing). Only plain relative paths inside the folder: a
/// hand-edited line naming "../x" or "/etc/x" is ignored.
std::set<std::filesystem::path> read_manifest(const std::filesystem::path& file);
/// The manifest's text: a comment saying what it is, then one path per line.
std::string manifest_text(const std::set<std::filesystem::path>& files);

/// fsync of a folder (its entries on the disk); failures are ignored.
void sync_folder(const std::filesystem::path& dir) noexcept;

/// Completes a commit: moves every file of `commit` into `dir`, removes the files the folder's manifest lists and the
/// commit's does not, moves the manifest last, removes `commit`. Each step can be repeated, so a commit interrupted
/// anywhere is completed by running this again. Returns the removed files. Throws OutputError (saying that the
/// folder is now a mix of two runs, and how it is completed) when a rename fails.
std::vector<std::filesystem::path> complete_commit(const std::filesystem::path& dir, const std::filesystem::path& commit);

} // namespace geartopo::output::detail
