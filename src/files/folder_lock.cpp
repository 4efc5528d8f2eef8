// The lock of an output folder (folder_lock.hpp).
#include "folder_lock.hpp"

#include "geartopo/files/output_folder.hpp"

#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace geartopo::output::detail {

namespace fs = std::filesystem;

namespace {

/// The refusal when another process holds the lock of `dir`: its pid, read from the open lock file `fd`.
OutputError held_by_another_run(const fs::path& dir, int fd) {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
  std::string pid = n > 0 ? std::string(text, static_cast<std::size_t>(n)) : std::string();
  while (!pid.empty() && std::isspace(static_cast<unsigned char>(pid.back()))) pid.pop_back();
  // The file names the holder only when the holder could write it: a pid that is not running is an earlier
  // holder's, left in a lock file that the present holder could only open read-only.
  char* end = nullptr;
  const long value = std::strtol(pid.c_str(), &end, 10);
  const bool named = !pid.empty() && end != nullptr && *end == '\0' && process_alive(value);
  return OutputError(dir, "another geartopo run (" +
                              (named ? "pid " + pid
                                     : std::string("its pid is unknown: ") + kLockName +
                                           " names no running process; another user's killed run may have left it") +
                              ") is writing into this folder: wait for it to end, or choose another --out");
}

} // namespace

bool process_alive(long pid) {
  if (pid <= 0) return false;
  if (pid == static_cast<long>(::getpid())) return true;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

// The lock file is removed by its holder when it is done; a lock taken on a file that was removed meanwhile is taken
// again on the file that is there. A lock file left by another user's killed run cannot be opened for writing (mode
// 0644): it is opened read-only (flock needs no write access) and, once locked, replaced by one of our own; where
// that cannot be done (a sticky folder) the lock is held on it as it is, without our pid.
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
      if (err == EWOULDBLOCK) {
        OutputError refusal = held_by_another_run(dir, fd);
        ::close(fd);
        throw refusal;
      }
      ::close(fd);
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

} // namespace geartopo::output::detail
