#include "app/work_estimates.hpp"

#include "app/messages.hpp"

#include "geartopo/pipeline/pipeline.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <thread>
#include <unistd.h>

namespace geartopo::app {

void print_work_estimate(long long points, long long flanks, bool exact, int passes) {
  if (points < kEstimateFromPoints || quiet()) return;
  const double rate = exact ? 1.5e6 : 2.9e6; // points/s, 2 cores (docs/performance.md)
  const std::string times = passes > 1 ? fmt::format(", {} times", passes) : std::string();
  const double seconds = static_cast<double>(points) * passes / rate;
  release_messages(); // long work: its estimate is seen now, what was said before it first
  std::fprintf(stderr, "geartopo: %s\n",
               fmt::format("{} points on {} flanks ({}{}): about {:.{}f} s on 2 cores", points, flanks,
                           exact ? "exact" : "linear", times, seconds, seconds < 10.0 ? 1 : 0)
                   .c_str());
}

SimulationWatch::SimulationWatch(std::string stage, long long flanks, int threads, double max_seconds,
                                 std::chrono::steady_clock::time_point job_start, std::string hint)
    : stage_(std::move(stage)),
      flanks_(flanks),
      threads_(static_cast<int>(std::max<long long>(
          1, std::min<long long>(flanks, threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency()))))),
      max_seconds_(max_seconds),
      job_start_(job_start),
      hint_(std::move(hint)),
      progress_(stage_, flanks, "flanks") {}

void SimulationWatch::flank_done(long long done, long long total) {
  if (done == 1 && flanks_ > 1) { // the first flank: every thread started one at the same time, this one finished first
    const auto now = std::chrono::steady_clock::now();
    const double first = std::chrono::duration<double>(now - start_).count();
    const double spent = std::chrono::duration<double>(now - job_start_).count();
    const long long rounds = (flanks_ + threads_ - 1) / threads_;
    const double estimate = first * static_cast<double>(rounds);
    const std::string what = fmt::format("{} {} flanks at {:.2g} s each on {} thread(s): about {:.{}f} s", stage_, flanks_,
                                         first, threads_, estimate, estimate < 10.0 ? 1 : 0);
    if (spent - first + estimate > max_seconds_)
      throw CLI::ValidationError("--max-time-s", fmt::format("the job would take too long: {}{}, beyond the limit of {:g} s "
                                                             "(--max-time-s): use {}",
                                                             what,
                                                             spent - first > 1.0
                                                                 ? fmt::format(" after {:.0f} s already spent", spent - first)
                                                                 : std::string(),
                                                             max_seconds_, hint_));
    if (!quiet() && estimate >= kPrintEstimateFromSeconds) {
      release_messages();
      std::fputs(fmt::format("{}geartopo: {}\n", ::isatty(STDERR_FILENO) != 0 ? "\r\033[K" : "", what).c_str(), stderr);
    }
  }
  progress_.update(done, total);
}

std::function<void(long long, long long)> SimulationWatch::callback() {
  return [this](long long done, long long total) { flank_done(done, total); };
}

MonteCarloWatch::MonteCarloWatch(long long samples, int threads, double max_seconds, std::string split_hint, bool adaptive)
    : samples_(samples),
      adaptive_(adaptive),
      threads_(static_cast<int>(std::min<long long>(
          samples, threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency())))),
      max_seconds_(max_seconds),
      split_hint_(std::move(split_hint)),
      progress_(pipeline::kPredictionStage, samples, "samples") {}

void MonteCarloWatch::prepared() {
  if (any_done_ || prepared_) return; // the first preparation only (an MPI rank prepares each adaptive batch)
  const auto now = std::chrono::steady_clock::now();
  preparation_s_ = std::chrono::duration<double>(now - start_).count();
  start_ = now;
  prepared_ = true;
}

void MonteCarloWatch::sample_done(long long done, long long total) {
  any_done_ = true;
  if (done == 1) { // the first sample: every thread started one at the same time, this one finished first
    const double first = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const long long rounds = (samples_ + threads_ - 1) / std::max(1, threads_);
    const double estimate = preparation_s_ + first * static_cast<double>(rounds);
    const std::string what = fmt::format("{} samples at {:.2g} s each on {} thread(s){}: about {:.{}f} s{}", samples_, first,
                                         threads_,
                                         prepared_ ? fmt::format(" after {:.2g} s of preparation", preparation_s_) : "",
                                         estimate, estimate < 10.0 ? 1 : 0,
                                         adaptive_ ? " at most (the adaptive run may stop earlier)" : "");
    if (estimate > max_seconds_)
      throw CLI::ValidationError("--samples", fmt::format("the Monte Carlo prediction would take too long: {}, beyond "
                                                          "the limit of {:g} s (--max-time-s): use fewer --samples or {}",
                                                          what, max_seconds_, split_hint_));
    if (!quiet() && ::isatty(STDERR_FILENO) != 0) {
      release_messages();
      std::fputs(fmt::format("\r\033[Kgeartopo: Monte Carlo: {}\n", what).c_str(), stderr);
    }
  }
  progress_.update(done, total);
}

std::function<void(long long, long long)> MonteCarloWatch::callback() {
  return [this](long long done, long long total) { sample_done(done, total); };
}

} // namespace geartopo::app
