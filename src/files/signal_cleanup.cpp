// What an interrupted run removes (termination.hpp), with async-signal-safe calls only in the handler's path.
#include "signal_cleanup.hpp"

#include "geartopo/files/termination.hpp"

#include <array>
#include <atomic>
#include <climits>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <string>
#include <sys/syscall.h>
#include <unistd.h>
#include <utility>

namespace geartopo::output {

namespace detail {

// The temporaries being written: a fixed table (no allocation, no lock in the handler). A slot is claimed by
// compare-exchange, filled, then published; the handler unlinks the published ones.
struct TemporarySlot {
  std::atomic<int> state{0}; // 0 free, 1 being filled or emptied, 2 published
  char path[PATH_MAX] = {};
};

namespace {

std::array<TemporarySlot, 64> temporary_slots;

// The staging folder and the lock file of the open OutputFolder (published like a temporary slot).
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

} // namespace

RegisteredTemporary::RegisteredTemporary(const std::filesystem::path& tmp) {
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

RegisteredTemporary::~RegisteredTemporary() {
  if (slot_ != nullptr) {
    slot_->state.store(1);
    slot_->path[0] = '\0';
    slot_->state.store(0);
  }
}

void publish_stage(const std::filesystem::path& stage) noexcept { publish(stage_published, stage_path, stage.native()); }

void forget_stage() noexcept { unpublish(stage_published, stage_path); }

void publish_lock(const std::filesystem::path& lock) noexcept { publish(lock_published, lock_path, lock.native()); }

void forget_lock() noexcept { unpublish(lock_published, lock_path); }

void publish_created_folders(const std::filesystem::path& deepest, std::size_t levels) noexcept {
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

void write_step() {
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

} // namespace detail

void remove_temporaries_in_progress() noexcept {
  for (auto& s : detail::temporary_slots)
    if (s.state.load() == 2) ::unlink(s.path);
  detail::remove_published_stage();
  detail::remove_published_lock();
  detail::remove_published_created_folders();
}

void remove_temporaries_on_termination_signals() {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    // A signal the parent set to be ignored stays ignored: `nohup` (SIGHUP), a shell's background job (SIGINT).
    struct sigaction now {};
    if (::sigaction(sig, nullptr, &now) == 0 && now.sa_handler == SIG_IGN) continue;
    std::signal(sig, detail::remove_temporaries_and_reraise);
  }
  std::signal(SIGXFSZ, SIG_IGN);
}

} // namespace geartopo::output
