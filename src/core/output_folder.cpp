#include "geartopo/core/output_folder.hpp"

#include "geartopo/core/atomic_file.hpp"

#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

namespace geartopo::output {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStagePrefix = ".gt-stage-";
constexpr const char* kCommitPrefix = ".gt-commit-";

// A process that cannot be signalled because it does not exist (ESRCH) is dead; EPERM means it exists.
bool process_alive(long pid) {
  if (pid <= 0) return false;
  if (pid == static_cast<long>(::getpid())) return true;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

std::set<fs::path> read_manifest(const fs::path& file) {
  std::set<fs::path> out;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line.front() == '#') continue;
    const fs::path rel = fs::path(line).lexically_normal();
    // Only plain relative paths inside the folder: a hand-edited manifest naming "../x" or "/etc/x" is ignored.
    if (rel.is_absolute() || rel.empty() || *rel.begin() == "..") continue;
    out.insert(rel);
  }
  return out;
}

std::string manifest_text(const std::set<fs::path>& files) {
  std::ostringstream text;
  text << "# geartopo: the files its last run wrote into this folder (relative paths). Files listed here that a later\n"
          "# run does not write are removed by that run (and a subfolder that leaves empty); nothing else in the folder\n"
          "# is touched.\n";
  for (const auto& f : files) text << f.generic_string() << "\n";
  return text.str();
}

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

void sync_folder(const fs::path& dir) noexcept {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// Completes a commit (output_folder.hpp): moves every file of `commit` into `dir`, removes the files the folder's
// manifest lists and the commit's does not, moves the manifest last, removes `commit`. Each step can be repeated, so
// a commit interrupted anywhere is completed by running this again. Returns the removed files.
std::vector<fs::path> complete_commit(const fs::path& dir, const fs::path& commit) {
  std::error_code ec;
  if (!fs::exists(commit / kManifestName, ec)) { // moved last: every other step is done
    fs::remove_all(commit, ec);
    return {};
  }
  const auto before = read_manifest(dir / kManifestName);
  const auto after = read_manifest(commit / kManifestName);
  std::vector<fs::path> files;
  for (auto it = fs::recursive_directory_iterator(commit, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    const fs::path rel = it->path().lexically_relative(commit);
    if (it->is_regular_file(ec) && rel != kManifestName) files.push_back(rel);
  }
  // A failure here (a full disk: a rename that must grow the folder fails with ENOSPC) leaves the folder a mix of
  // the two runs; the commit folder stays, readers refuse the folder (input_file.hpp), the next run completes it.
  const auto unfinished = [&](const std::string& what) {
    std::string reason = what;
    reason += "; the folder now holds files of two runs: the next geartopo run with --out ";
    reason += dir.string();
    reason += " completes this commit (";
    reason += commit.filename().string();
    reason += "), and until then geartopo refuses to read from the folder";
    return reason;
  };
  if (ec) throw OutputError(commit, unfinished("cannot read the files to move in: " + ec.message()));
  for (const auto& rel : files) {
    const fs::path target = dir / rel;
    std::error_code mk;
    fs::create_directories(target.parent_path(), mk);
    if (::rename((commit / rel).c_str(), target.c_str()) != 0) throw OutputError(target, unfinished(std::strerror(errno)));
    staging::step();
  }
  std::vector<fs::path> removed;
  for (const auto& old : before) {
    if (after.count(old) != 0) continue;
    std::error_code rm;
    const fs::path p = dir / old;
    if (!fs::is_regular_file(fs::symlink_status(p, rm)) || !fs::remove(p, rm)) continue;
    removed.push_back(old);
    // A subfolder that held only geartopo's files goes with them (meshes/ of a run that wrote no meshes this time);
    // rmdir removes only an empty folder, so one holding anything else, the user's files, stays.
    for (fs::path sub = old.parent_path(); !sub.empty(); sub = sub.parent_path())
      if (::rmdir((dir / sub).c_str()) != 0) break;
  }
  if (::rename((commit / kManifestName).c_str(), (dir / kManifestName).c_str()) != 0)
    throw OutputError(dir / kManifestName, unfinished(std::strerror(errno)));
  staging::step();
  fs::remove_all(commit, ec);
  sync_folder(dir);
  return removed;
}

// flock(2) on the folder's lock file, which then holds our pid. The lock file is removed by its holder when it is
// done; a lock taken on a file that was removed meanwhile is taken again on the file that is there. A lock file left
// by another user's killed run cannot be opened for writing (mode 0644): it is opened read-only (flock needs no write
// access) and, once locked, replaced by one of our own; where that cannot be done (a sticky folder) the lock is held
// on it as it is, without our pid.
int take_lock(const fs::path& dir) {
  const fs::path lock = dir / kLockName;
  for (int attempt = 0; attempt < 100; ++attempt) {
    bool writable = true;
    int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0 && errno == EACCES) {
      writable = false;
      fd = ::open(lock.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    }
    if (fd < 0) throw OutputError(dir, std::string("cannot create its lock file ") + kLockName + ": " + std::strerror(errno));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      char text[32] = {};
      const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
      ::close(fd);
      std::string pid = n > 0 ? std::string(text, static_cast<std::size_t>(n)) : std::string();
      while (!pid.empty() && std::isspace(static_cast<unsigned char>(pid.back()))) pid.pop_back();
      // The file names the holder only when the holder could write it: a pid that is not running is an earlier
      // holder's, left in a lock file that the present holder could only open read-only.
      char* end = nullptr;
      const long value = std::strtol(pid.c_str(), &end, 10);
      const bool named = !pid.empty() && end != nullptr && *end == '\0' && process_alive(value);
      if (err == EWOULDBLOCK)
        throw OutputError(dir, "another geartopo run (" +
                                   (named ? "pid " + pid
                                          : std::string("its pid is unknown: ") + kLockName +
                                                " names no running process; another user's killed run may have left it") +
                                   ") is writing into this folder: wait for it to end, or choose another --out");
      throw OutputError(dir, std::string("cannot lock it: ") + std::strerror(err));
    }
    struct stat held {}, there {};
    if (::fstat(fd, &held) != 0 || ::stat(lock.c_str(), &there) != 0 || held.st_dev != there.st_dev ||
        held.st_ino != there.st_ino) {
      ::close(fd); // removed or replaced meanwhile: lock the file that is there now
      continue;
    }
    if (!writable) {
      // A dead run's lock file that is not ours: replaced by our own if the folder lets us remove it.
      if (::unlink(lock.c_str()) == 0) {
        ::close(fd);
        continue;
      }
      return fd;
    }
    const std::string pid = std::to_string(::getpid()) + "\n";
    if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) < 0) {
      // The pid is only for the message of a refused second run; the lock holds without it.
    }
    return fd;
  }
  throw OutputError(dir, "cannot lock it: its lock file keeps changing");
}

} // namespace

bool is_geartopo_temporary(const std::string& name, long& pid) {
  // ".gt-<pid>-<n><ext>" only: the ".<stem>.tmp-<pid>-<n><ext>" names of earlier versions also match users' files
  // (".notes.tmp-2024-11.md"), and a clean-up must never take one of those.
  if (!starts_with(name, ".gt-")) return false;
  std::size_t i = 4, digits = 0;
  long value = 0;
  while (i < name.size() && std::isdigit(static_cast<unsigned char>(name[i])) && digits < 10)
    value = value * 10 + (name[i++] - '0'), ++digits;
  if (digits == 0 || i >= name.size() || name[i] != '-') return false;
  ++i;
  std::size_t counter_digits = 0;
  while (i < name.size() && std::isdigit(static_cast<unsigned char>(name[i]))) ++i, ++counter_digits;
  if (counter_digits == 0) return false;
  if (i < name.size() && name[i] != '.') return false;
  pid = value;
  return true;
}

std::string unfinished_commit(const fs::path& folder) {
  std::error_code ec;
  for (auto it = fs::directory_iterator(folder, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (starts_with(name, kCommitPrefix)) return name;
  }
  return {};
}

void check_run_files(const fs::path& dir, const RunFiles& files) {
  check_name_lengths(dir);
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir, ec)) && !fs::is_directory(dir, ec)) throw OutputError(dir, "it is a file, not a folder");
  for (const auto& in : files.inputs) note_input(in);
  const auto listed = read_manifest(dir / kManifestName);
  for (const auto& out : files.outputs) {
    const fs::path file = dir / out;
    check_not_an_input(file);
    struct stat st {};
    if (::lstat(file.c_str(), &st) == 0 && listed.count(out.lexically_normal()) == 0)
      throw OutputError(file, staging::foreign_file_reason(dir));
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
  if (!created_folders_.empty()) staging::publish_created_folders(created_folders_.front(), created_folders_.size());
  if (!fs::is_directory(dir_)) {
    const std::string reason = ec ? "cannot create the folder: " + ec.message() : "it is not a folder";
    remove_created_folders();
    throw OutputError(dir, reason);
  }
  try {
    lock_fd_ = take_lock(dir_);
    // What killed runs left: a commit is completed, a staging folder removed (we hold the lock: their writers are
    // gone).
    for (auto it = fs::directory_iterator(dir_, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
      const auto& e = *it;
      const std::string name = e.path().filename().string();
      std::error_code type;
      if (!e.is_directory(type) || e.is_symlink(type)) continue;
      if (starts_with(name, kCommitPrefix)) {
        complete_commit(dir_, e.path());
        removed_temporaries_.push_back(name);
      } else if (starts_with(name, kStagePrefix)) {
        fs::remove_all(e.path(), ec);
        removed_temporaries_.push_back(name);
      }
    }
    // Temporaries of dead processes: in the folder itself and in the subfolders its manifest names files in
    // (meshes/, panels/), not below; nothing but ".gt-PID-N" names.
    previous_ = read_manifest(dir_ / kManifestName);
    std::set<fs::path> folders{fs::path()};
    for (const auto& f : previous_) folders.insert(f.parent_path());
    for (const auto& rel : folders) {
      const fs::path folder = rel.empty() ? dir_ : dir_ / rel;
      std::error_code it_ec;
      if (!rel.empty() && (fs::is_symlink(folder, it_ec) || !fs::is_directory(folder, it_ec))) continue;
      for (auto it = fs::directory_iterator(folder, it_ec); !it_ec && it != fs::directory_iterator(); it.increment(it_ec)) {
        long pid = 0;
        std::error_code type;
        if (!it->is_regular_file(type) || it->is_symlink(type) || !is_geartopo_temporary(it->path().filename().string(), pid))
          continue;
        if (process_alive(pid)) continue;
        std::error_code rm;
        if (fs::remove(it->path(), rm)) removed_temporaries_.push_back(it->path().lexically_relative(dir_));
      }
    }
    check_run_files(dir_, files);
    stage_ = dir_ / (kStagePrefix + std::to_string(::getpid()));
    fs::remove_all(stage_, ec);
    if (!fs::create_directory(stage_, ec) || ec)
      throw OutputError(dir_, "cannot create its staging folder " + stage_.filename().string() + ": " + ec.message());
    staging::begin(dir_, stage_, previous_, dir_ / kLockName);
    staging_ = true;
  } catch (...) {
    release();
    remove_created_folders();
    throw;
  }
}

std::vector<fs::path> OutputFolder::finish() {
  if (!staging_) return {};
  auto listed = staging::end();
  staging_ = false;
  // An earlier run's file that this run read (evaluate --traces D/traces.csv --out D) is not removed: it stays listed.
  for (const auto& old : previous_)
    if (listed.count(old) == 0 && is_an_input(dir_ / old)) listed.insert(old);
  std::vector<fs::path> removed;
  try {
    write_text_atomically(stage_ / kManifestName, manifest_text(listed)); // a full disk here: nothing has changed yet
    sync_folder(stage_);
    const fs::path commit = dir_ / (kCommitPrefix + std::to_string(::getpid()));
    staging::enter_commit();
    if (::rename(stage_.c_str(), commit.c_str()) != 0) {
      const int err = errno;
      staging::leave_commit();
      throw OutputError(dir_, std::string("cannot commit its files: ") + std::strerror(err));
    }
    sync_folder(dir_); // the commit point is on the disk
    try {
      removed = complete_commit(dir_, commit);
    } catch (...) {
      staging::leave_commit(); // the commit folder stays: the next run into this folder completes it
      throw;
    }
    staging::leave_commit();
  } catch (...) {
    std::error_code ec;
    fs::remove_all(stage_, ec);
    staging::forget_stage();
    release();
    remove_created_folders(); // only those still empty: after a commit failed midway the folder holds files
    throw;
  }
  release();
  created_folders_.clear(); // the run succeeded: its folders stay
  staging::forget_created_folders();
  return removed;
}

void OutputFolder::release() noexcept {
  if (lock_fd_ < 0) return;
  staging::forget_lock();
  ::unlink((dir_ / kLockName).c_str()); // still held: a run that opened it meanwhile takes the lock again (take_lock)
  ::close(lock_fd_);
  lock_fd_ = -1;
}

OutputFolder::~OutputFolder() {
  if (staging_) {
    try {
      staging::end();
    } catch (...) {
    }
    std::error_code ec;
    fs::remove_all(stage_, ec);
    staging::forget_stage();
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
  staging::forget_created_folders();
}

} // namespace geartopo::output
