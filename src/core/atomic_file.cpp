#include "geartopo/core/atomic_file.hpp"

#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <fstream>
#include <map>
#include <mutex>
#include <sys/stat.h>
#include <sys/syscall.h>
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

// The staging folder and the lock file of the open OutputFolder, for the signal handler (published like a
// temporary slot).
std::atomic<int> stage_published{0}; // 0 none, 1 being changed, 2 published
char stage_path[PATH_MAX] = {};
std::atomic<int> lock_published{0};
char lock_path[PATH_MAX] = {};
// The folders the open OutputFolder created: the deepest, and how many levels up from it (all were missing).
std::atomic<int> created_published{0};
char created_path[PATH_MAX] = {};
std::atomic<std::size_t> created_levels{0};

bool publish(std::atomic<int>& state, char* buffer, const std::string& text) {
  if (text.size() >= PATH_MAX) return false;
  int expected = 0;
  if (!state.compare_exchange_strong(expected, 1)) return false;
  std::memcpy(buffer, text.c_str(), text.size() + 1);
  state.store(2);
  return true;
}

void unpublish(std::atomic<int>& state, char* buffer) noexcept {
  int expected = 2;
  if (state.compare_exchange_strong(expected, 1)) {
    buffer[0] = '\0';
    state.store(0);
  }
}

// 0: running; 1: an OutputFolder commits (a termination signal waits for the end of the commit); 2: a termination
// signal is being handled (no commit may start).
std::atomic<int> signal_state{0};
std::atomic<int> pending_signal{0};

// Removes the tree below the open folder `fd` with async-signal-safe calls only (getdents64, openat, unlinkat).
void remove_tree_at(int fd, int depth) noexcept {
  struct Dirent64 {
    std::uint64_t d_ino;
    std::int64_t d_off;
    unsigned short d_reclen;
    unsigned char d_type;
    char d_name[1];
  };
  alignas(8) char buffer[4096];
  // Entries removed while the folder is read may shift the listing: read it again until a pass removes nothing.
  for (int pass = 0; pass < 64; ++pass) {
    bool removed = false;
    ::lseek(fd, 0, SEEK_SET);
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
      if (n <= 0) break;
      for (long at = 0; at < n;) {
        const auto* d = reinterpret_cast<const Dirent64*>(buffer + at);
        at += d->d_reclen;
        const char* name = d->d_name;
        if (name[0] == '.' && (name[1] == '\0' || (name[1] == '.' && name[2] == '\0'))) continue;
        if (d->d_type == DT_DIR) {
          if (depth < 16) {
            const int sub = ::openat(fd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
            if (sub >= 0) {
              remove_tree_at(sub, depth + 1);
              ::close(sub);
            }
          }
          removed = ::unlinkat(fd, name, AT_REMOVEDIR) == 0 || removed;
        } else {
          removed = ::unlinkat(fd, name, 0) == 0 || removed;
        }
      }
    }
    if (!removed) break;
  }
}

void remove_published_stage() noexcept {
  if (stage_published.load() != 2) return;
  const int fd = ::open(stage_path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  remove_tree_at(fd, 0);
  ::close(fd);
  ::rmdir(stage_path);
}

void remove_published_lock() noexcept {
  if (lock_published.load() == 2) ::unlink(lock_path);
}

// rmdir, deepest first, of the folders the run created; stops at the first that is not empty.
void remove_published_created_folders() noexcept {
  if (created_published.load() != 2) return;
  char path[PATH_MAX];
  std::memcpy(path, created_path, sizeof path);
  for (std::size_t level = created_levels.load(); level > 0; --level) {
    if (::rmdir(path) != 0) return;
    char* slash = std::strrchr(path, '/');
    if (slash == nullptr || slash == path) return;
    *slash = '\0';
  }
}

extern "C" void remove_temporaries_and_reraise(int sig) {
  int expected = 0;
  if (!signal_state.compare_exchange_strong(expected, 2) && expected == 1) {
    pending_signal.store(sig); // a commit runs: it completes, then leave_commit() delivers the signal
    return;
  }
  remove_temporaries_in_progress();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// The folder being staged: writes below `dir` go to `stage`.
struct Staging {
  bool active = false;
  fs::path dir, stage;
  std::set<fs::path> replaceable;
  std::map<fs::path, fs::path> staged; // final (absolute, normal) → staged copy
};
std::mutex staging_mutex;
Staging& staging_state() {
  static Staging s;
  return s;
}

// The inputs of this run (note_input): device and inode of each, with the name it was given.
struct InputFile {
  dev_t dev;
  ino_t ino;
  std::string name;
};
std::mutex inputs_mutex;
std::vector<InputFile>& input_files() {
  static std::vector<InputFile> list;
  return list;
}

fs::path absolute_normal(const fs::path& file) {
  std::error_code ec;
  fs::path p = fs::absolute(file, ec);
  if (ec) p = file;
  return p.lexically_normal();
}

// Where `file` is written: its staged copy when it lies in the folder being staged (whose parent folders are then
// made), else `file`. While a folder is staged (a command runs), refuses an input of the run and a file in that
// folder that geartopo did not write. (Without an open folder, in a library or a test, "this run" is not defined:
// a file read earlier may be written again, as before.)
fs::path destination_for(const fs::path& file) {
  const std::lock_guard lock(staging_mutex);
  Staging& s = staging_state();
  if (!s.active) return file;
  check_not_an_input(file);
  const fs::path abs = absolute_normal(file);
  const fs::path rel = abs.lexically_relative(s.dir);
  if (rel.empty() || *rel.begin() == ".." || rel == ".") return file;
  if (*rel.begin() == s.stage.filename()) return file; // the staging folder itself (the manifest written by finish)
  struct stat st {};
  if (s.replaceable.count(rel) == 0 && ::lstat(abs.c_str(), &st) == 0) {
    throw OutputError(file, staging::foreign_file_reason(s.dir));
  }
  const fs::path staged = s.stage / rel;
  std::error_code ec;
  fs::create_directories(staged.parent_path(), ec);
  if (ec) throw OutputError(file, "cannot create its staging folder: " + ec.message());
  return staged;
}

void record_staged(const fs::path& file, const fs::path& staged) {
  if (staged == file) return;
  const std::lock_guard lock(staging_mutex);
  staging_state().staged[absolute_normal(file)] = staged;
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
    throw OutputError(file, S_ISDIR(st.st_mode) ? "it is a directory" : "it is not a regular file (a device, FIFO or socket is never replaced)");
  const fs::path destination = destination_for(file);
  const fs::path dir = destination.has_parent_path() ? destination.parent_path() : fs::path(".");
  if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) throw OutputError(file, "its folder does not exist");
  return destination;
}

// "<folder>/.gt-<pid>-<n><ext>": hidden, unique per process and call, same extension as the final name, and short
// (at most 41 bytes), so that a final name of NAME_MAX bytes still has a temporary.
fs::path temporary_for(const fs::path& file) {
  static std::atomic<unsigned> counter{0};
  std::string name = ".gt-";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  const std::string ext = file.extension().string();
  if (ext.size() <= 16) name += ext;
  return file.parent_path() / name;
}

// Flushes the temporary to the disk (a rename before the data is on the disk could leave an empty file after a
// crash), then renames it over the final name. Removes the temporary on failure.
// `file` names the final file in messages; `destination` is where it goes now (itself, or its staged copy).
void sync_and_rename(const fs::path& tmp, const fs::path& destination, const fs::path& file) {
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
  if (::rename(tmp.c_str(), destination.c_str()) != 0) {
    const int err = errno;
    std::error_code ec;
    fs::remove(tmp, ec);
    throw OutputError(file, errno_text(err));
  }
  record_staged(file, destination);
  staging::step();
}

} // namespace

OutputError::OutputError(const fs::path& file, const std::string& reason)
    : std::runtime_error(message(file, reason)), file_(file) {}

void write_atomically(const fs::path& file, const std::function<void(std::ostream&)>& write) {
  const fs::path destination = check_target(file);
  const fs::path tmp = temporary_for(destination);
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
    std::error_code ec;
    fs::remove(tmp, ec);
    throw OutputError(file, err != 0 ? errno_text(err) : std::string("write error"));
  }
  sync_and_rename(tmp, destination, file);
}

void write_atomically_via_path(const fs::path& file, const std::function<void(const fs::path&)>& write) {
  const fs::path destination = check_target(file);
  const fs::path tmp = temporary_for(destination);
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
  sync_and_rename(tmp, destination, file);
}

void write_text_atomically(const fs::path& file, std::string_view text) {
  write_atomically(file, [&](std::ostream& out) { out.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

fs::path current_location(const fs::path& file) {
  const std::lock_guard lock(staging_mutex);
  const auto& staged = staging_state().staged;
  const auto it = staged.find(absolute_normal(file));
  return it != staged.end() ? it->second : file;
}

void check_name_lengths(const fs::path& path) {
  for (const auto& part : path)
    if (part.native().size() > NAME_MAX)
      throw OutputError(path, "the name '" + part.string().substr(0, 40) + "…' is " + std::to_string(part.native().size()) +
                                  " bytes long, more than the " + std::to_string(NAME_MAX) + " a file or folder name may have");
}

void note_input(const fs::path& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) return;
  const std::lock_guard lock(inputs_mutex);
  for (auto& i : input_files())
    if (i.dev == st.st_dev && i.ino == st.st_ino) {
      i.name = file.string(); // the same file under another name, or a removed input's inode reused
      return;
    }
  input_files().push_back({st.st_dev, st.st_ino, file.string()});
}

namespace {
const InputFile* find_input(const fs::path& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) return nullptr;
  for (const auto& i : input_files()) {
    if (i.dev != st.st_dev || i.ino != st.st_ino) continue;
    // Still the input under its name? An input removed since it was read may have left its inode to a new file.
    struct stat now {};
    if (::stat(i.name.c_str(), &now) == 0 && now.st_dev == i.dev && now.st_ino == i.ino) return &i;
  }
  return nullptr;
}
} // namespace

bool is_an_input(const fs::path& file) {
  const std::lock_guard lock(inputs_mutex);
  return find_input(file) != nullptr;
}

void check_not_an_input(const fs::path& output) {
  const std::lock_guard lock(inputs_mutex);
  if (const InputFile* i = find_input(output))
    throw OutputError(output, "it is " + i->name + ", an input of this run: geartopo never replaces what it reads; "
                                "choose another output name or folder");
}

void remove_temporaries_in_progress() noexcept {
  for (auto& s : temporary_slots)
    if (s.state.load() == 2) ::unlink(s.path);
  remove_published_stage();
  remove_published_lock();
  remove_published_created_folders();
}

void remove_temporaries_on_termination_signals() {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    // A signal the parent set to be ignored stays ignored: `nohup` (SIGHUP), a shell's background job (SIGINT).
    struct sigaction now {};
    if (::sigaction(sig, nullptr, &now) == 0 && now.sa_handler == SIG_IGN) continue;
    std::signal(sig, remove_temporaries_and_reraise);
  }
  std::signal(SIGXFSZ, SIG_IGN);
}

void create_folders_for(const fs::path& dir) {
  {
    const std::lock_guard lock(staging_mutex);
    const Staging& s = staging_state();
    if (s.active) {
      const fs::path rel = absolute_normal(dir).lexically_relative(s.dir);
      if (!rel.empty() && *rel.begin() != "..") return; // staged writes make their folders in the staging folder
    }
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw OutputError(dir, "cannot create the folder: " + ec.message());
}

namespace staging {

std::string foreign_file_reason(const fs::path& dir) {
  std::string reason = "a file geartopo did not write is there (it is not listed in ";
  reason += (dir / ".geartopo-outputs").string();
  reason += "): geartopo never replaces it; move it away or choose another --out";
  return reason;
}

void begin(const fs::path& dir, const fs::path& stage, std::set<fs::path> replaceable, const fs::path& lock) {
  {
    const std::lock_guard lock(staging_mutex);
    Staging& s = staging_state();
    // One folder per command: a second would take the first one's writes.
    if (s.active) throw OutputError(dir, "another output folder (" + s.dir.string() + ") is open in this process");
    s.active = true;
    s.dir = dir;
    s.stage = stage;
    s.replaceable = std::move(replaceable);
    s.staged.clear();
  }
  publish(stage_published, stage_path, stage.native());
  publish(lock_published, lock_path, lock.native());
}

std::set<fs::path> end() {
  std::set<fs::path> out;
  {
    const std::lock_guard lock(staging_mutex);
    Staging& s = staging_state();
    for (const auto& [file, staged] : s.staged) out.insert(file.lexically_relative(s.dir));
    s = Staging{};
  }
  return out;
}

void forget_stage() noexcept { unpublish(stage_published, stage_path); }

void forget_lock() noexcept { unpublish(lock_published, lock_path); }

void publish_created_folders(const fs::path& deepest, std::size_t levels) noexcept {
  unpublish(created_published, created_path);
  created_levels.store(levels);
  publish(created_published, created_path, deepest.native());
}

void forget_created_folders() noexcept { unpublish(created_published, created_path); }

void enter_commit() noexcept {
  int expected = 0;
  // A termination signal is being handled: the process ends in a moment, before anything is moved.
  while (!signal_state.compare_exchange_strong(expected, 1)) {
    if (expected == 1) return;
    ::pause();
    expected = 0;
  }
}

void leave_commit() {
  forget_stage();
  int expected = 1;
  signal_state.compare_exchange_strong(expected, 0);
  if (const int sig = pending_signal.exchange(0); sig != 0) remove_temporaries_and_reraise(sig);
}

void step() {
  static const std::pair<int, long> at = [] {
    const char* v = std::getenv("GEARTOPO_TEST_SIGNAL_AT");
    int sig = 0;
    long k = 0;
    if (v == nullptr || std::sscanf(v, "%d:%ld", &sig, &k) != 2) return std::pair<int, long>{0, 0};
    return std::pair<int, long>{sig, k};
  }();
  static std::atomic<long> steps{0};
  if (at.first != 0 && ++steps == at.second) ::kill(::getpid(), at.first);
}

} // namespace staging

} // namespace geartopo::output
