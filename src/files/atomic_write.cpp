// Writing through a temporary beside the final file (atomic_write.hpp): checked, synced, renamed.
#include "geartopo/files/atomic_write.hpp"

#include "signal_cleanup.hpp"
#include "staging.hpp"
#include "temporary_name.hpp"

#include <cerrno>
#include <climits>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <string>
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

void remove_quietly(const fs::path& tmp) {
  std::error_code ec;
  fs::remove(tmp, ec);
}

// Refuses what must never be replaced by a rename, and a folder that is not there (the temporary could not be made).
// Returns where the file is written now (destination_for): the folder checked is that one's (a staged write makes
// its folder in the staging folder).
fs::path check_target(const fs::path& file) {
  if (file.empty()) throw OutputError(file, "an empty file name");
  if (!file.has_filename()) throw OutputError(file, "a folder name, not a file name");
  check_name_lengths(file);
  struct stat st {};
  if (::stat(file.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw OutputError(file, S_ISDIR(st.st_mode) ? "it is a directory"
                                                : "it is not a regular file (a device, FIFO or socket is never replaced)");
  const fs::path destination = detail::destination_for(file);
  const fs::path dir = destination.has_parent_path() ? destination.parent_path() : fs::path(".");
  if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) throw OutputError(file, "its folder does not exist");
  return destination;
}

// Flushes the temporary to the disk (a rename before the data is on the disk could leave an empty file after a
// crash), then renames it over the final name. Removes the temporary on failure.
// `file` names the final file in messages; `destination` is where it goes now (itself, or its staged copy).
void sync_and_rename(const fs::path& tmp, const fs::path& destination, const fs::path& file) {
  const int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    remove_quietly(tmp);
    throw OutputError(file, with_errno("the temporary file is gone", err));
  }
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    remove_quietly(tmp);
    throw OutputError(file, errno_text(err));
  }
  ::close(fd);
  if (::rename(tmp.c_str(), destination.c_str()) != 0) {
    const int err = errno;
    remove_quietly(tmp);
    throw OutputError(file, errno_text(err));
  }
  detail::record_staged(file, destination);
  detail::write_step();
}

} // namespace

OutputError::OutputError(const fs::path& file, const std::string& reason)
    : std::runtime_error(message(file, reason)), file_(file) {}

void write_atomically(const fs::path& file, const std::function<void(std::ostream&)>& write) {
  const fs::path destination = check_target(file);
  const fs::path tmp = detail::temporary_for(destination);
  const detail::RegisteredTemporary registered(tmp);
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) throw OutputError(file, with_errno("cannot create a temporary file beside it", errno));
  try {
    write(out);
  } catch (...) {
    out.close();
    remove_quietly(tmp);
    throw;
  }
  // A stream that failed while `write` wrote (a file-size limit, a full disk) still holds the failed write()'s errno.
  int write_err = !out ? errno : 0;
  // The stream buffers: a full disk often shows only at the flush or the close, so both are checked.
  if (out) {
    errno = 0;
    out.flush();
    write_err = errno;
  }
  const bool written = static_cast<bool>(out);
  out.close();
  if (!written || out.fail()) {
    const int err = write_err != 0 ? write_err : errno;
    remove_quietly(tmp);
    throw OutputError(file, err != 0 ? errno_text(err) : std::string("write error"));
  }
  sync_and_rename(tmp, destination, file);
}

void write_atomically_via_path(const fs::path& file, const std::function<void(const fs::path&)>& write) {
  const fs::path destination = check_target(file);
  const fs::path tmp = detail::temporary_for(destination);
  const detail::RegisteredTemporary registered(tmp);
  try {
    write(tmp);
  } catch (...) {
    remove_quietly(tmp);
    throw;
  }
  struct stat st {};
  if (::stat(tmp.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
    remove_quietly(tmp);
    throw OutputError(file, "the writer left no file");
  }
  sync_and_rename(tmp, destination, file);
}

void write_text_atomically(const fs::path& file, std::string_view text) {
  write_atomically(file, [&](std::ostream& out) { out.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

void check_name_lengths(const fs::path& path) {
  for (const auto& part : path)
    if (part.native().size() > NAME_MAX)
      throw OutputError(path, "the name '" + part.string().substr(0, 40) + "…' is " +
                                  std::to_string(part.native().size()) + " bytes long, more than the " +
                                  std::to_string(NAME_MAX) + " a file or folder name may have");
}

} // namespace geartopo::output
