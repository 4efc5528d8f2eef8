// Internal: one writer per output folder (output_folder.hpp, "One writer"): flock(2) on its lock file.
#pragma once

#include <filesystem>

namespace geartopo::output::detail {

/// True when process `pid` is running (this process included); a process that cannot be signalled because it does
/// not exist (ESRCH) is dead, one that refuses (EPERM) exists.
bool process_alive(long pid);

/// Takes the lock of `dir` (its file kLockName, which then holds our pid) and returns its file descriptor. Throws
/// OutputError naming the holder's pid when another run holds it, or when the lock file cannot be made.
int take_lock(const std::filesystem::path& dir);

} // namespace geartopo::output::detail
