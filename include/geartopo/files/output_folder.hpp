// geartopo — the folder a command writes its outputs into (`--out DIR`). The folder changes all at once or not at all:
//
//  * Staging. While the folder is open, every file the command writes into it goes to a staging folder inside it
//    (".gt-stage-PID", same relative paths; atomic_write.hpp redirects the writes). A run that fails, runs out of disk
//    or is interrupted by SIGINT/SIGTERM/SIGHUP removes its staging folder: the folder keeps the earlier run's files.
//    It also removes the folders it created (the folder and missing parents, deepest first, rmdir: only if empty).
//  * Commit. finish() writes the new manifest into the staging folder, renames the staging folder to ".gt-commit-PID"
//    (one rename: the commit point), then moves each file into place, removes the files of the earlier run that this
//    one did not write (and the subfolders that leaves empty), moves the manifest last and removes the empty commit
//    folder. Termination signals wait for the end of the commit. A rename that fails within it (a full disk) leaves
//    the commit folder, as a SIGKILL does; the error says so. The folder is not swapped whole with one rename
//    because it may hold the user's own files, which stay.
//  * Recovery. A process killed by SIGKILL (or a crash) leaves a ".gt-stage-*" folder (not committed: removed, the
//    earlier files are intact) or, if it died within the commit's renames (milliseconds), a ".gt-commit-*" folder:
//    the next command that opens the folder completes that commit, so the folder then holds the new run's files.
//    Until then the folder is a mix, and readers (input_file.hpp) refuse its files (unfinished_commit).
//  * One writer. The folder is locked (flock(2) on ".geartopo-lock", which holds the writer's pid) from opening to
//    the end of finish() or of the failed run; a second geartopo run is refused, naming the folder and the pid. The
//    lock of a dead process is free by itself; its lock file, if another user's (not writable), is locked read-only
//    and replaced by one's own where the folder allows (not in a sticky folder: then the pid is not recorded).
//    Commands open their folder before their computation (under MPI rank 0 alone, which alone writes), so a second
//    run is refused at once.
//  * Manifest. What geartopo wrote is recorded in kManifestName (one path per line, relative to the folder). A run
//    never replaces a file that is not listed there (the user's own), nor a file it reads as an input (both refused
//    with OutputError naming the two paths); the files the manifest lists that this run did not write are removed
//    when it succeeds, so no figure or table of an earlier run can be mistaken for this one's.
// Temporaries of killed geartopo processes (".gt-PID-N.ext" only) are removed on opening, from the folder and the
// subfolders its manifest names files in; no other file is touched.
#pragma once

#include "geartopo/files/output_error.hpp"

#include <cstddef>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace geartopo::output {

inline constexpr const char* kManifestName = ".geartopo-outputs";
inline constexpr const char* kLockName = ".geartopo-lock";

/// What a run reads and what it will write into its folder, declared before any computation so that a refusal
/// costs nothing. Outputs are paths relative to the folder; the run may write others (figures, meshes), which are
/// checked when they are written.
struct RunFiles {
  std::vector<std::filesystem::path> inputs;
  std::vector<std::filesystem::path> outputs;
};

/// Throws OutputError when a declared output of a run into `dir` would replace one of its inputs or an existing file
/// the folder's manifest does not list. Creates nothing; for commands to call before their computation.
void check_run_files(const std::filesystem::path& dir, const RunFiles& files);

class OutputFolder {
public:
  /// Creates `dir` (and its parents) if needed, takes its lock, completes or removes what killed runs left (see
  /// above), checks `files` (check_run_files) and starts staging. Throws OutputError when `dir` cannot be created or
  /// is not a folder, when another run holds the lock, when a declared output is refused, or when another
  /// OutputFolder is open in this process (one per command).
  explicit OutputFolder(const std::filesystem::path& dir, const RunFiles& files = {});
  /// Without finish() (the run failed): the staged files are removed and the folder is as it was (a folder this run
  /// created is removed if empty). Never throws.
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::filesystem::path& path() const noexcept { return dir_; }

  /// The run succeeded: commits its files (see above). Returns the removed files of the earlier run (relative to the
  /// folder), for the command's message.
  std::vector<std::filesystem::path> finish();

  /// The stale temporaries and staging folders removed when the folder was opened (relative paths).
  const std::vector<std::filesystem::path>& removed_temporaries() const noexcept { return removed_temporaries_; }

private:
  void release() noexcept;
  void remove_created_folders() noexcept;

  std::filesystem::path dir_, stage_;
  std::set<std::filesystem::path> previous_;
  std::vector<std::filesystem::path> removed_temporaries_;
  int lock_fd_ = -1;
  bool staging_ = false;
  std::vector<std::filesystem::path> created_folders_; ///< the folder and parents this run created, deepest first
};

/// The name of a commit folder (".gt-commit-PID") in `folder`, or "" when there is none: the folder is then a mix of
/// two runs until the commit completes (by its writer within milliseconds, or by the next run into the folder if the
/// writer was killed or failed). Readers (input_file.hpp) refuse to read from such a folder.
std::string unfinished_commit(const std::filesystem::path& folder);

/// True for the name of a writer's temporary (".gt-PID-N.ext"); `pid` receives PID.
bool is_geartopo_temporary(const std::string& filename, long& pid);

} // namespace geartopo::output
