// geartopo — the inputs of this run: every file a reader opens (input_file.hpp) is recorded by device and inode, so
// that no output of the same run replaces it (atomic_write.hpp, output_folder.hpp refuse such a write by name).
#pragma once

#include <filesystem>

namespace geartopo::output {

/// Records `file` as an input of this run (input_file.hpp calls it for every file it opens): no output may then
/// replace it. `file` need not exist.
void note_input(const std::filesystem::path& file);

/// True when `file` exists and is an input of this run (note_input).
bool is_an_input(const std::filesystem::path& file);

/// Throws OutputError naming `output` and the input when `output` is an existing file this run reads (note_input):
/// for commands to check their outputs before any computation.
void check_not_an_input(const std::filesystem::path& output);

} // namespace geartopo::output
