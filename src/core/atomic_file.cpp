#include "geartopo/core/atomic_file.hpp"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

namespace geartopo::output {

namespace fs = std::filesystem;

namespace {

std::string message(const fs::path& file, const std::string& reason) {
  // Built by appending: GCC 12 warns falsely (-Wrestrict) on `"literal" + std::string&&`.
  std::string m = file.string();
  m += ": cannot write: ";
  m += reason;
  return m;
}

std::string errno_text(int err) { return std::strerror(err); }

std::string with_errno(std::string text, int err) {
  text += ": ";
  text += std::strerror(err);
  return text;
}

// Refuses what must never be replaced by a rename, and a folder that is not there (the temporary could not be made).
void check_target(const fs::path& file) {
  if (file.empty()) throw OutputError(file, "an empty file name");
  if (!file.has_filename()) throw OutputError(file, "a folder name, not a file name");
  struct stat st {};
  if (::stat(file.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw OutputError(file, S_ISDIR(st.st_mode) ? "it is a directory" : "it is not a regular file (a device, FIFO or socket is never replaced)");
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) throw OutputError(file, "its folder does not exist");
}

// "<folder>/.<stem>.tmp-<pid>-<n><ext>": hidden, unique per process and call, same extension as the final name.
fs::path temporary_for(const fs::path& file) {
  static std::atomic<unsigned> counter{0};
  std::string name = ".";
  name += file.stem().string();
  name += ".tmp-";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  name += file.extension().string();
  return file.parent_path() / name;
}

// Flushes the temporary to the disk (a rename before the data is on the disk could leave an empty file after a
// crash), then renames it over the final name. Removes the temporary on failure.
void sync_and_rename(const fs::path& tmp, const fs::path& file) {
  const int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    std::error_code ec;
    fs::remove(tmp, ec);
    throw OutputError(file, with_errno("the temporary file is gone", err));
  }
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    std::error_code ec;
    fs::remove(tmp, ec);
    throw OutputError(file, errno_text(err));
  }
  ::close(fd);
  if (::rename(tmp.c_str(), file.c_str()) != 0) {
    const int err = errno;
    std::error_code ec;
    fs::remove(tmp, ec);
    throw OutputError(file, errno_text(err));
  }
}

} // namespace

OutputError::OutputError(const fs::path& file, const std::string& reason)
    : std::runtime_error(message(file, reason)), file_(file) {}

void write_atomically(const fs::path& file, const std::function<void(std::ostream&)>& write) {
  check_target(file);
  const fs::path tmp = temporary_for(file);
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) throw OutputError(file, with_errno("cannot create a temporary file beside it", errno));
  try {
    write(out);
  } catch (...) {
    out.close();
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  // The stream buffers: a full disk often shows only at the flush or the close, so both are checked.
  errno = 0;
  out.flush();
  const bool written = static_cast<bool>(out);
  const int write_err = errno;
  out.close();
  if (!written || out.fail()) {
    const int err = write_err != 0 ? write_err : errno;
    std::error_code ec;
    fs::remove(tmp, ec);
    throw OutputError(file, err != 0 ? errno_text(err) : std::string("write error"));
  }
  sync_and_rename(tmp, file);
}

void write_atomically_via_path(const fs::path& file, const std::function<void(const fs::path&)>& write) {
  check_target(file);
  const fs::path tmp = temporary_for(file);
  try {
    write(tmp);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  struct stat st {};
  if (::stat(tmp.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw OutputError(file, "the writer left no file");
  }
  sync_and_rename(tmp, file);
}

void write_text_atomically(const fs::path& file, std::string_view text) {
  write_atomically(file, [&](std::ostream& out) { out.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

} // namespace geartopo::output
