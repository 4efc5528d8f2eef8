#include "geartopo/core/atomic_file.hpp"

#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <mutex>
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

// The final files written so far (files_written).
std::mutex written_mutex;
std::vector<fs::path>& written_list() {
  static std::vector<fs::path> list;
  return list;
}

void record_written(const fs::path& file) {
  std::error_code ec;
  fs::path p = fs::absolute(file, ec);
  if (ec) p = file;
  const std::lock_guard lock(written_mutex);
  written_list().push_back(p.lexically_normal());
}

// The temporaries being written, for the signal handler: a fixed table (no allocation, no lock in the handler). A
// slot is claimed by compare-exchange, filled, then published; the handler unlinks the published ones. When every
// slot is taken the temporary goes unregistered (OutputFolder's clean-up of dead processes' leftovers still
// removes it later).
struct TemporarySlot {
  std::atomic<int> state{0}; // 0 free, 1 being filled or emptied, 2 published
  char path[PATH_MAX] = {};
};
std::array<TemporarySlot, 64> temporary_slots;

class RegisteredTemporary {
public:
  explicit RegisteredTemporary(const fs::path& tmp) {
    const std::string& text = tmp.native();
    if (text.size() >= PATH_MAX) return;
    for (auto& s : temporary_slots) {
      int expected = 0;
      if (s.state.compare_exchange_strong(expected, 1)) {
        std::memcpy(s.path, text.c_str(), text.size() + 1);
        s.state.store(2);
        slot_ = &s;
        return;
      }
    }
  }
  ~RegisteredTemporary() {
    if (slot_ != nullptr) {
      slot_->state.store(1);
      slot_->path[0] = '\0';
      slot_->state.store(0);
    }
  }
  RegisteredTemporary(const RegisteredTemporary&) = delete;
  RegisteredTemporary& operator=(const RegisteredTemporary&) = delete;

private:
  TemporarySlot* slot_ = nullptr;
};

extern "C" void remove_temporaries_and_reraise(int sig) {
  remove_temporaries_in_progress();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
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
  record_written(file);
}

} // namespace

OutputError::OutputError(const fs::path& file, const std::string& reason)
    : std::runtime_error(message(file, reason)), file_(file) {}

void write_atomically(const fs::path& file, const std::function<void(std::ostream&)>& write) {
  check_target(file);
  const fs::path tmp = temporary_for(file);
  const RegisteredTemporary registered(tmp);
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
  const RegisteredTemporary registered(tmp);
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

std::vector<fs::path> files_written() {
  const std::lock_guard lock(written_mutex);
  return written_list();
}

void remove_temporaries_in_progress() noexcept {
  for (auto& s : temporary_slots)
    if (s.state.load() == 2) ::unlink(s.path);
}

void remove_temporaries_on_termination_signals() {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, remove_temporaries_and_reraise);
}

} // namespace geartopo::output
