#include "app/progress.hpp"

#include "app/messages.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <unistd.h>

namespace geartopo::app {

struct Progress::State {
  std::string what, unit;
  std::atomic<long long> total{0}, done{0};
  // `active` is read by every worker before it takes the lock (the cheap early return) and cleared by finish():
  // atomic, so that read is not a data race. `shown` and `last` are touched only under `mutex`.
  std::atomic<bool> active{false};
  bool shown = false;
  std::mutex mutex;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now(), last;
};

Progress::Progress(std::string what, long long total, std::string unit) : state_(std::make_unique<State>()) {
  state_->what = std::move(what);
  state_->unit = std::move(unit);
  state_->total = total;
  state_->active = !quiet() && ::isatty(STDERR_FILENO) != 0;
  if (state_->active && total <= 0) { // no count yet: the stage's name, until a count or the next line replaces it
    release_messages();
    std::fputs(fmt::format("\rgeartopo: {} …\033[K", state_->what).c_str(), stderr);
    std::fflush(stderr);
    state_->shown = true;
  }
}

Progress::~Progress() { finish(); }

void Progress::finish() {
  const std::lock_guard lock(state_->mutex);
  if (state_->shown) std::fputs("\r\033[K", stderr);
  state_->shown = false;
  state_->active = false;
}

void Progress::advance(long long n) {
  long long done = state_->done += n;
  const long long total = state_->total;
  if (!state_->active || total <= 0) return;
  // The last unit waits for the line (it must show "total/total"); the others skip it while another worker prints.
  std::unique_lock lock(state_->mutex, std::defer_lock);
  if (done >= total)
    lock.lock();
  else if (!lock.try_lock())
    return;
  if (!state_->active) return; // finished
  done = state_->done;         // a worker that waited may hold an older count
  const auto now = std::chrono::steady_clock::now();
  if (state_->shown && now - state_->last < std::chrono::milliseconds(200) && done < total) return;
  state_->last = now;
  if (!state_->shown) release_messages(); // the work has started: what was said before it goes first
  state_->shown = true;
  const double s = std::chrono::duration<double>(now - state_->start).count();
  // Time left at the rate so far (the units of one stage cost about the same: flanks, samples, fits).
  const std::string left = done > 0 && done < total
                               ? fmt::format(", about {:.0f} s left", s * static_cast<double>(total - done) / static_cast<double>(done))
                               : std::string();
  std::fputs(fmt::format("\rgeartopo: {} {}/{} {}, {:.0f} s{}\033[K", state_->what, std::min(done, total), total,
                         state_->unit, s, left)
                 .c_str(),
             stderr);
  std::fflush(stderr);
}

void Progress::update(long long done, long long total) {
  // Raise the total to `total` if larger; a compare-exchange loop, so two workers reporting at once keep the larger.
  long long known = state_->total.load();
  while (total > known && !state_->total.compare_exchange_weak(known, total)) {
  }
  const long long before = state_->done.load();
  if (done > before) advance(done - before);
}

std::function<void(long long, long long)> Progress::callback() {
  return [this](long long done, long long total) { update(done, total); };
}

} // namespace geartopo::app
