// geartopo — writing an output file atomically: everything is written to a temporary file in the same folder, the
// write is checked, flushed to the disk and closed, and only then renamed to the final name. A full disk, a quota, a
// file-size limit (SIGXFSZ is ignored, so the write fails with EFBIG) or any exception while writing leaves no file
// (old or partial) under the final name that was not completely written, removes the temporary and throws
// OutputError naming the final file. Every writer of geartopo (topology and traces CSV, JSON, YAML scenes, correction
// tables, meshes, PNGs) goes through here.
//
// Staging (output_folder.hpp): while an OutputFolder is open, a file written into its folder goes to the folder's
// staging folder instead (same relative path); OutputFolder::finish() moves the staged files in at the end, so that
// the folder changes all at once. A write into the folder is refused when the file there is an input of this run or
// a file geartopo did not write (not in the folder's manifest).
//
// Temporary names are short (".gt-PID-N.ext"), so that any legal final name (NAME_MAX = 255 bytes) can be written.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace geartopo::output {

/// A file could not be written; what() is "<file>: cannot write: <reason>".
class OutputError : public std::runtime_error {
public:
  OutputError(const std::filesystem::path& file, const std::string& reason);
  const std::filesystem::path& file() const noexcept { return file_; }

private:
  std::filesystem::path file_;
};

/// Writes `file` through `write(stream)`. The stream is checked after `write` returns; a failed stream, an exception
/// from `write` (rethrown as is) or a failed flush, sync or rename removes the temporary. Refuses an empty name, a
/// name longer than NAME_MAX, a folder that does not exist, a final name that is not a regular file (a directory,
/// /dev/full, a FIFO: never replaced), and, while an OutputFolder is open, a file this process read as an input
/// (note_input).
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

/// Records `file` as an input of this run (core/input_file.hpp calls it for every file it opens): no output may then
/// replace it. `file` need not exist.
void note_input(const std::filesystem::path& file);

/// Throws OutputError when a file or folder name in `path` is longer than NAME_MAX (255 bytes).
void check_name_lengths(const std::filesystem::path& path);

/// True when `file` exists and is an input of this run (note_input).
bool is_an_input(const std::filesystem::path& file);

/// Throws OutputError naming `output` and the input when `output` is an existing file this run reads (note_input):
/// for commands to check their outputs before any computation.
void check_not_an_input(const std::filesystem::path& output);

/// Removes the temporaries being written right now, and the staging folder, the lock file and the (then empty) folders
/// created by an open OutputFolder. Async-signal-safe
/// (getdents64, unlinkat): for the SIGINT/SIGTERM/SIGHUP handler of the program, so that an interrupted run leaves no
/// temporary and no staged file behind. A SIGKILL cannot be handled: OutputFolder removes such leftovers of dead
/// processes the next time a command writes into the folder.
void remove_temporaries_in_progress() noexcept;

/// Installs the program's handling of signals for its outputs: SIGINT, SIGTERM and SIGHUP run
/// remove_temporaries_in_progress (deferred while an OutputFolder commits, so that its commit completes), then restore
/// the default action and re-raise the signal, so the exit status still says what killed the process; SIGXFSZ (a
/// file-size limit, `ulimit -f`) is ignored, so that the write fails with EFBIG and is reported like a full disk. A
/// signal that is ignored when this is called (`nohup`: SIGHUP; a shell's background job: SIGINT) stays ignored.
void remove_temporaries_on_termination_signals();

/// Makes the folder `dir` for files to be written into it (a figure's panels/). Inside the open OutputFolder's folder
/// nothing is made: the staged writes make their folders in the staging folder, and the folder appears with the
/// commit, only if a file was written into it. Elsewhere `dir` and its parents are created; throws OutputError when
/// that fails.
void create_folders_for(const std::filesystem::path& dir);

namespace staging {
// The interface of OutputFolder (output_folder.cpp) to the writers; not for commands.

/// Redirects writes below `dir` (absolute, normal) into `stage` (a folder inside `dir`). `replaceable` holds the
/// relative paths geartopo may replace (the manifest); any other existing file below `dir` is refused. The signal
/// handler removes `stage` and the folder's `lock` file.
void begin(const std::filesystem::path& dir, const std::filesystem::path& stage, std::set<std::filesystem::path> replaceable,
           const std::filesystem::path& lock);
/// The reason given when a run would replace a file below `dir` that is not in the manifest.
std::string foreign_file_reason(const std::filesystem::path& dir);
/// Ends the redirection; returns the relative paths staged since begin().
std::set<std::filesystem::path> end();
/// Stops the signal handler's removal of the staging folder (it was moved in or removed).
void forget_stage() noexcept;
/// Stops the signal handler's removal of the lock file (the folder is about to release it).
void forget_lock() noexcept;
/// The signal handler removes (rmdir: only if empty) `deepest` and the `levels` - 1 folders above it, which this run
/// created; until forget_created_folders().
void publish_created_folders(const std::filesystem::path& deepest, std::size_t levels) noexcept;
void forget_created_folders() noexcept;
/// While an OutputFolder commits, a SIGINT/SIGTERM/SIGHUP is held and delivered by leave_commit().
void enter_commit() noexcept;
void leave_commit();
/// Test hook: the environment variable GEARTOPO_TEST_SIGNAL_AT="SIG:K" makes the process send itself signal SIG
/// (a number) at the K-th step of its write phase (a staged file written, a file moved in by the commit), so that
/// tests can interrupt a run at every point. Without the variable, nothing.
void step();

} // namespace staging

} // namespace geartopo::output
