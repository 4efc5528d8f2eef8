// geartopo — writing an output file atomically: everything is written to a temporary file in the same folder, the
// write is checked, flushed to the disk and closed, and only then renamed to the final name. A full disk, a quota, a
// file-size limit (SIGXFSZ is ignored, termination.hpp, so the write fails with EFBIG) or any exception while writing
// leaves no file (old or partial) under the final name that was not completely written, removes the temporary and
// throws OutputError naming the final file. Every writer of geartopo (topology and traces CSV, JSON, YAML scenes,
// correction tables, meshes, PNGs) goes through here.
//
// While an OutputFolder is open (output_folder.hpp), a file written into its folder goes to the folder's staging
// folder instead (same relative path), and the folder changes all at once when the command ends. A write into the
// folder is refused when the file there is an input of this run (input_registry.hpp) or a file geartopo did not
// write (not in the folder's manifest).
//
// Temporary names are short (".gt-PID-N.ext"), so that any legal final name (NAME_MAX = 255 bytes) can be written.
#pragma once

#include "geartopo/files/output_error.hpp"

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string_view>

namespace geartopo::output {

/// Writes `file` through `write(stream)`. The stream is checked after `write` returns; a failed stream, an exception
/// from `write` (rethrown as is) or a failed flush, sync or rename removes the temporary. Refuses an empty name, a
/// name longer than NAME_MAX, a folder that does not exist, a final name that is not a regular file (a directory,
/// /dev/full, a FIFO: never replaced), and, while an OutputFolder is open, a file this process read as an input
/// (input_registry.hpp).
void write_atomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& write);

/// The same for writers that need a path of their own (OpenMesh, PNG encoders): `write(temporary)` writes the
/// temporary (same folder, same extension, so that writers choosing a format by extension choose the same one), which
/// must then exist as a regular file; it is synced and renamed to `file`.
void write_atomically_via_path(const std::filesystem::path& file,
                               const std::function<void(const std::filesystem::path&)>& write);

/// write_atomically of a text.
void write_text_atomically(const std::filesystem::path& file, std::string_view text);

/// Where `file`, written by this run, can be read now: its staged copy while its output folder is still open, else
/// `file` itself. For writers that read back what they wrote (a figure's panels).
std::filesystem::path current_location(const std::filesystem::path& file);

/// Makes the folder `dir` for files to be written into it (a figure's panels/). Inside the open OutputFolder's folder
/// nothing is made: the staged writes make their folders in the staging folder, and the folder appears with the
/// commit, only if a file was written into it. Elsewhere `dir` and its parents are created; throws OutputError when
/// that fails.
void create_folders_for(const std::filesystem::path& dir);

/// Throws OutputError when a file or folder name in `path` is longer than NAME_MAX (255 bytes).
void check_name_lengths(const std::filesystem::path& path);

} // namespace geartopo::output
