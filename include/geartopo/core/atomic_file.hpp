// geartopo — writing an output file atomically: everything is written to a temporary file in the same folder, the
// write is checked, flushed to the disk and closed, and only then renamed to the final name. A full disk, a quota, a
// file-size limit or any exception while writing leaves no file (old or partial) under the final name that was not
// completely written, removes the temporary and throws OutputError naming the final file. Every writer of geartopo
// (topology and traces CSV, JSON, YAML scenes, correction tables, meshes, PNGs) goes through here.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
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
/// folder that does not exist, and a final name that is not a regular file (a directory, /dev/full, a FIFO: never
/// replaced).
void write_atomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& write);

/// The same for writers that need a path of their own (OpenMesh, PNG encoders): `write(temporary)` writes the
/// temporary (same folder, same extension, so that writers choosing a format by extension choose the same one), which
/// must then exist as a regular file; it is synced and renamed to `file`.
void write_atomically_via_path(const std::filesystem::path& file,
                               const std::function<void(const std::filesystem::path&)>& write);

/// write_atomically of a text.
void write_text_atomically(const std::filesystem::path& file, std::string_view text);

/// Every final file this process has written through write_atomically*, in order (absolute, lexically normal
/// paths). OutputFolder uses it to know what a command produced. Thread-safe.
std::vector<std::filesystem::path> files_written();

/// Removes the temporaries being written right now. Async-signal-safe (unlink only): for the SIGINT/SIGTERM/SIGHUP
/// handler of the program, so that an interrupted run leaves no ".name.tmp-PID-N" file behind. A SIGKILL cannot be
/// handled: OutputFolder removes such leftovers of dead processes the next time a command writes into the folder.
void remove_temporaries_in_progress() noexcept;

/// Installs remove_temporaries_in_progress as the handler of SIGINT, SIGTERM and SIGHUP; the handler then restores
/// the default action and re-raises the signal, so the exit status still says what killed the process.
void remove_temporaries_on_termination_signals();

} // namespace geartopo::output
