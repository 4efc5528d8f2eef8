// geartopo — what a command says on stderr besides its results: notes, warnings, files removed. Errors first: the
// messages are held while the command runs, so that a command that fails prints its error as the first stderr line.
// The hold and --quiet belong to the process's one stderr, so they are the process's (thread-safe), not a
// command's.
#pragma once

#include <string>
#include <string_view>

namespace geartopo::output {
class OutputFolder;
}
namespace geartopo::workbench {
struct Workbench;
}

namespace geartopo::app {

/// `--quiet` (any subcommand): no progress, work estimates or notes on stderr; warnings and errors stay.
void set_quiet(bool quiet);
bool quiet();

/// Errors first: what a command says on stderr (its banner, notes, warnings, files removed) goes through say() and is
/// held from hold_messages() on, so that a command that fails prints its error as the first stderr line and what it
/// had said after it (main: take_held_messages()); one that succeeds prints it when it ends. Long work releases the
/// hold (release_messages()) before its work estimate or progress line, which must be seen while it runs: a failure
/// after that (a full disk) follows them. Thread-safe.
void hold_messages();
/// `line` and a newline on stderr, or held.
void say(std::string_view line);
/// Prints what is held and stops holding.
void release_messages();
/// What is held (lines with their newlines), and stops holding.
std::string take_held_messages();

/// Closes a command's output folder (files/output_folder.hpp): removes what an earlier run wrote and this one did
/// not, and says so on stderr (unless --quiet).
void finish_output_folder(output::OutputFolder& folder);

/// The workbench's notes (what was chosen for the user, e.g. a wheel diameter) on stderr, unless --quiet.
void print_notes(const workbench::Workbench& wb);

} // namespace geartopo::app
