// geartopo — progress of long work on stderr: one line rewritten in place, on a terminal only.
#pragma once

#include <functional>
#include <memory>
#include <string>

namespace geartopo::app {

/// Progress of long work on stderr: one line rewritten in place ("geartopo: simulate 35/70 flanks, 12 s"), only when
/// stderr is a terminal and --quiet is not given, at most every 0.2 s; scripts and logs see nothing. Thread-safe:
/// `advance` may be called from parallel_for's workers. The line is cleared when the object goes.
class Progress {
public:
  Progress(std::string what, long long total, std::string unit);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  void advance(long long done_now = 1);
  /// (done, total) as a library reports them; a total > 0 replaces the one given at construction (the diagnosis
  /// learns its number of pair fits on the way).
  void update(long long done, long long total);
  /// Clears the line (before the command prints its results); the destructor does it too.
  void finish();
  /// A callback for libraries that report (done, total) themselves: update().
  std::function<void(long long, long long)> callback();

private:
  struct State;
  std::unique_ptr<State> state_;
};

} // namespace geartopo::app
