// geartopo — long work says its cost up front (issues 18, 25): the expected wall time of a simulation or a Monte
// Carlo prediction, printed before or while it runs, and the job refused when it would exceed --max-time-s.
#pragma once

#include "app/progress.hpp"

#include <atomic>
#include <chrono>
#include <functional>
#include <string>

namespace geartopo::app {

/// Before a long simulation (at least kEstimateFromPoints points; not with --quiet, on a terminal or in a log): one
/// line with the number of points and flanks and the expected wall time at the rates of docs/performance.md
/// (exact ≈ 1.5 M, linear ≈ 2.9 M points/s on 2 cores). `passes`: how often the job simulates them (run and report:
/// the gear before and after compensation, 2).
inline constexpr long long kEstimateFromPoints = 1'000'000;
void print_work_estimate(long long points, long long flanks, bool exact, int passes = 1);

/// Longest simulate, run or report job (estimated wall time, s) started unless --max-time-s says otherwise: one day,
/// as the Monte Carlo's (kMaxMonteCarloSeconds).
inline constexpr double kMaxJobSeconds = 86'400.0;

/// The measured work estimate of a simulation stage (issue 25: long work says its cost up front), fed by
/// grinding::SimulationOptions::progress. When the first flank is done: the stage's wall time ≈ its measured time ×
/// ⌈flanks / threads⌉ (the threads take flanks one after another, all of about the same cost). The job is refused
/// when the time it has already spent (since `job_start`) plus this stage's estimate exceeds max_seconds
/// (--max-time-s): CLI::ValidationError naming --max-time-s with the estimate and the limit (exit 2), thrown from the
/// progress callback so that no further flank starts (core/parallel.hpp stops on the first exception). The estimate
/// is printed (not with --quiet) when it is at least kPrintEstimateFromSeconds; the Progress line follows on a
/// terminal. Thread-safe.
class SimulationWatch {
public:
  static constexpr double kPrintEstimateFromSeconds = 10.0;
  /// `stage` names the work ("simulate"); `threads` as SimulationOptions::threads (0: all hardware threads);
  /// `hint` says how to make the work smaller (e.g. "a coarser grid (--dense) or fewer --teeth").
  SimulationWatch(std::string stage, long long flanks, int threads, double max_seconds,
                  std::chrono::steady_clock::time_point job_start, std::string hint);
  void flank_done(long long done, long long total);
  /// For SimulationOptions::progress: flank_done() of this object, which must outlive the simulation.
  std::function<void(long long, long long)> callback();
  /// Clears the progress line (before the results are printed).
  void finish() { progress_.finish(); }

private:
  std::string stage_;
  long long flanks_;
  int threads_;
  double max_seconds_;
  std::chrono::steady_clock::time_point job_start_, start_ = std::chrono::steady_clock::now();
  std::string hint_;
  Progress progress_;
};

/// The work estimate and progress of a Monte Carlo run (issue 18: work estimated before it starts), fed by
/// pipeline::MonteCarloOptions::on_sample_done. When the first sample is done: estimated wall time = the
/// preparation's measured time (on_prepared) + the first sample's × ⌈samples / threads⌉ (the threads draw samples one
/// after another, all of the same cost). Printed on a terminal (not with --quiet); beyond max_seconds (--max-time-s,
/// monte_carlo_flags.hpp) the run is refused — CLI::ValidationError naming --samples with the estimate and the limit
/// (exit 2, as --dense beyond the simulation's bound), thrown from on_sample_done so that no further sample starts.
/// Then the samples done and the time left on the Progress line. Thread-safe.
class MonteCarloWatch {
public:
  /// `samples` in this run (this shard's), `threads` as MonteCarloOptions::threads (0: all hardware threads);
  /// `split_hint` says how to split the work (e.g. "--shard i/n on several machines and geartopo merge").
  /// `adaptive`: `samples` is the adaptive run's limit (--max-samples), the estimate an upper bound.
  MonteCarloWatch(long long samples, int threads, double max_seconds, std::string split_hint, bool adaptive = false);
  void sample_done(long long done, long long total);
  /// For MonteCarloOptions::on_prepared: the samples start now. The estimate is then the preparation's measured time
  /// (sensitivities, the exact samples that check them) plus the first sample's time × ⌈samples / threads⌉. Only the
  /// first call counts, and none after a sample is done.
  void prepared();
  /// For MonteCarloOptions::on_sample_done: sample_done() of this object, which must outlive the run.
  std::function<void(long long, long long)> callback();

private:
  long long samples_;
  bool adaptive_;
  int threads_;
  double max_seconds_;
  std::string split_hint_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::atomic<bool> any_done_{false};
  bool prepared_ = false;
  double preparation_s_ = 0.0;
  Progress progress_;
};

} // namespace geartopo::app
