// geartopo — what an interrupted run leaves: nothing. The program installs the handling of termination signals
// once (main), and an interrupted write leaves no temporary, no staging folder, no lock file and no folder it created.
#pragma once

namespace geartopo::output {

/// Removes the temporaries being written right now, and the staging folder, the lock file and the (then empty)
/// folders created by an open OutputFolder. Async-signal-safe (getdents64, unlinkat): for the SIGINT/SIGTERM/SIGHUP
/// handler of the program, so that an interrupted run leaves no temporary and no staged file behind. A SIGKILL cannot
/// be handled: OutputFolder removes such leftovers of dead processes the next time a command writes into the folder.
void remove_temporaries_in_progress() noexcept;

/// Installs the program's handling of signals for its outputs: SIGINT, SIGTERM and SIGHUP run
/// remove_temporaries_in_progress (deferred while an OutputFolder commits, so that its commit completes), then restore
/// the default action and re-raise the signal, so the exit status still says what killed the process; SIGXFSZ (a
/// file-size limit, `ulimit -f`) is ignored, so that the write fails with EFBIG and is reported like a full disk. A
/// signal that is ignored when this is called (`nohup`: SIGHUP; a shell's background job: SIGINT) stays ignored.
void remove_temporaries_on_termination_signals();

} // namespace geartopo::output
