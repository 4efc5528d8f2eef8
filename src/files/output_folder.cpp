// The folder a command writes its outputs into (output_folder.hpp): opened (lock, recovery, staging), committed.
#include "geartopo/files/output_folder.hpp"

#include "commit.hpp"
#include "folder_lock.hpp"
#include "signal_cleanup.hpp"
#include "staging.hpp"

#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/input_registry.hpp"

#include <cerrno>
#include <cstring>
#include <sys/stat.h>
#include <unistd.h>

namespace geartopo::output {

namespace fs = std::filesystem;

namespace {

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

/// What killed runs left in `dir` (whose lock we hold: their writers are gone): a commit folder is completed, a
/// staging folder removed. Returns their names.
std::vector<fs::path> recover_killed_runs(const fs::path& dir) {
  std::vector<fs::path> removed;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const auto& e = *it;
    const std::string name = e.path().filename().string();
    std::error_code type;
    if (!e.is_directory(type) || e.is_symlink(type)) continue;
    if (starts_with(name, detail::kCommitPrefix)) {
      detail::complete_commit(dir, e.path());
      removed.push_back(name);
    } else if (starts_with(name, detail::kStagePrefix)) {
      fs::remove_all(e.path(), ec);
      removed.push_back(name);
    }
  }
  return removed;
}

/// Temporaries of dead processes: in `dir` itself and in the subfolders its manifest (`listed`) names files in
/// (meshes/, panels/), not below; nothing but ".gt-PID-N" names. Returns them, relative to `dir`.
std::vector<fs::path> remove_dead_temporaries(const fs::path& dir, const std::set<fs::path>& listed) {
  std::vector<fs::path> removed;
  std::set<fs::path> folders{fs::path()};
  for (const auto& f : listed) folders.insert(f.parent_path());
  for (const auto& rel : folders) {
    const fs::path folder = rel.empty() ? dir : dir / rel;
    std::error_code it_ec;
    if (!rel.empty() && (fs::is_symlink(folder, it_ec) || !fs::is_directory(folder, it_ec))) continue;
    for (auto it = fs::directory_iterator(folder, it_ec); !it_ec && it != fs::directory_iterator(); it.increment(it_ec)) {
      long pid = 0;
      std::error_code type;
      if (!it->is_regular_file(type) || it->is_symlink(type) || !is_geartopo_temporary(it->path().filename().string(), pid))
        continue;
      if (detail::process_alive(pid)) continue;
      std::error_code rm;
      if (fs::remove(it->path(), rm)) removed.push_back(it->path().lexically_relative(dir));
    }
  }
  return removed;
}

} // namespace

void check_run_files(const fs::path& dir, const RunFiles& files) {
  check_name_lengths(dir);
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir, ec)) && !fs::is_directory(dir, ec)) throw OutputError(dir, "it is a file, not a folder");
  for (const auto& in : files.inputs) note_input(in);
  const auto listed = detail::read_manifest(dir / kManifestName);
  for (const auto& out : files.outputs) {
    const fs::path file = dir / out;
    check_not_an_input(file);
    struct stat st {};
    if (::lstat(file.c_str(), &st) == 0 && listed.count(out.lexically_normal()) == 0)
      throw OutputError(file, detail::foreign_file_reason(dir));
  }
}

OutputFolder::OutputFolder(const fs::path& dir, const RunFiles& files) : dir_(dir) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir_, ec)) && !fs::is_directory(dir_, ec))
    throw OutputError(dir_, "it is a file, not a folder");
  check_name_lengths(dir_);
  dir_ = fs::absolute(dir_, ec).lexically_normal();
  if (!dir_.has_filename()) dir_ = dir_.parent_path(); // "D/" → "D"
  // The folders this run creates (D and any missing parents), deepest first: a failed run removes them again.
  for (fs::path p = dir_; p.has_relative_path() && !fs::exists(fs::symlink_status(p, ec)); p = p.parent_path())
    created_folders_.push_back(p);
  fs::create_directories(dir_, ec);
  if (!created_folders_.empty()) detail::publish_created_folders(created_folders_.front(), created_folders_.size());
  if (!fs::is_directory(dir_)) {
    const std::string reason = ec ? "cannot create the folder: " + ec.message() : "it is not a folder";
    remove_created_folders();
    throw OutputError(dir, reason);
  }
  try {
    lock_fd_ = detail::take_lock(dir_);
    removed_temporaries_ = recover_killed_runs(dir_);
    previous_ = detail::read_manifest(dir_ / kManifestName);
    const auto dead = remove_dead_temporaries(dir_, previous_);
    removed_temporaries_.insert(removed_temporaries_.end(), dead.begin(), dead.end());
    check_run_files(dir_, files);
    stage_ = dir_ / (detail::kStagePrefix + std::to_string(::getpid()));
    fs::remove_all(stage_, ec);
    if (!fs::create_directory(stage_, ec) || ec)
      throw OutputError(dir_, "cannot create its staging folder " + stage_.filename().string() + ": " + ec.message());
    detail::begin_staging(dir_, stage_, previous_);
    detail::publish_stage(stage_);
    detail::publish_lock(dir_ / kLockName);
    staging_ = true;
  } catch (...) {
    release();
    remove_created_folders();
    throw;
  }
}

std::vector<fs::path> OutputFolder::finish() {
  if (!staging_) return {};
  auto listed = detail::end_staging();
  staging_ = false;
  // An earlier run's file that this run read (evaluate --traces D/traces.csv --out D) is not removed: it stays listed.
  for (const auto& old : previous_)
    if (listed.count(old) == 0 && is_an_input(dir_ / old)) listed.insert(old);
  std::vector<fs::path> removed;
  try {
    write_text_atomically(stage_ / kManifestName, detail::manifest_text(listed)); // a full disk: nothing has changed
    detail::sync_folder(stage_);
    const fs::path commit = dir_ / (detail::kCommitPrefix + std::to_string(::getpid()));
    detail::enter_commit();
    if (::rename(stage_.c_str(), commit.c_str()) != 0) {
      const int err = errno;
      detail::leave_commit();
      throw OutputError(dir_, std::string("cannot commit its files: ") + std::strerror(err));
    }
    detail::sync_folder(dir_); // the commit point is on the disk
    try {
      removed = detail::complete_commit(dir_, commit);
    } catch (...) {
      detail::leave_commit(); // the commit folder stays: the next run into this folder completes it
      throw;
    }
    detail::leave_commit();
  } catch (...) {
    std::error_code ec;
    fs::remove_all(stage_, ec);
    detail::forget_stage();
    release();
    remove_created_folders(); // only those still empty: after a commit failed midway the folder holds files
    throw;
  }
  release();
  created_folders_.clear(); // the run succeeded: its folders stay
  detail::forget_created_folders();
  return removed;
}

void OutputFolder::release() noexcept {
  if (lock_fd_ < 0) return;
  detail::forget_lock();
  ::unlink((dir_ / kLockName).c_str()); // still held: a run that opened it meanwhile takes the lock again (take_lock)
  ::close(lock_fd_);
  lock_fd_ = -1;
}

OutputFolder::~OutputFolder() {
  if (staging_) {
    try {
      detail::end_staging();
    } catch (...) {
    }
    std::error_code ec;
    fs::remove_all(stage_, ec);
    detail::forget_stage();
    release();
    remove_created_folders();
  }
  release();
}

void OutputFolder::remove_created_folders() noexcept {
  // Deepest first; rmdir removes only an empty folder, so one that holds anything (someone else's files) stays.
  for (const auto& f : created_folders_)
    if (::rmdir(f.c_str()) != 0) break;
  created_folders_.clear();
  detail::forget_created_folders();
}

} // namespace geartopo::output
