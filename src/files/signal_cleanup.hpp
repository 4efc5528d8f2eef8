// Internal: what the termination-signal handler removes (termination.hpp). The writers publish the temporary being
// written, and the open OutputFolder its staging folder, its lock file and the folders it created, in fixed buffers
// that the handler reads without a lock or an allocation (async-signal-safe).
#pragma once

#include <cstddef>
#include <filesystem>

namespace geartopo::output::detail {

struct TemporarySlot;

/// The temporary `tmp` is published for the handler while this lives. When every slot is taken the temporary goes
/// unregistered (OutputFolder's clean-up of dead processes' leftovers still removes it later).
class RegisteredTemporary {
public:
  explicit RegisteredTemporary(const std::filesystem::path& tmp);
  ~RegisteredTemporary();
  RegisteredTemporary(const RegisteredTemporary&) = delete;
  RegisteredTemporary& operator=(const RegisteredTemporary&) = delete;

private:
  TemporarySlot* slot_ = nullptr;
};

/// The handler removes the staging folder `stage` (its tree) until forget_stage() (it was moved in or removed).
void publish_stage(const std::filesystem::path& stage) noexcept;
void forget_stage() noexcept;
/// The handler removes the folder's lock file until forget_lock() (the folder is about to release it).
void publish_lock(const std::filesystem::path& lock) noexcept;
void forget_lock() noexcept;
/// The handler removes (rmdir: only if empty) `deepest` and the `levels` - 1 folders above it, which this run
/// created; until forget_created_folders().
void publish_created_folders(const std::filesystem::path& deepest, std::size_t levels) noexcept;
void forget_created_folders() noexcept;

/// While an OutputFolder commits, a SIGINT/SIGTERM/SIGHUP is held and delivered by leave_commit(), which also
/// forgets the staging folder (it became the commit folder).
void enter_commit() noexcept;
void leave_commit();

/// Test hook: the environment variable GEARTOPO_TEST_SIGNAL_AT="SIG:K" makes the process send itself signal SIG
/// (a number) at the K-th step of its write phase (a staged file written, a file moved in by the commit), so that
/// tests can interrupt a run at every point. Without the variable, nothing.
void write_step();

} // namespace geartopo::output::detail
