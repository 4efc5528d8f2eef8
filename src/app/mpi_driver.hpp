// geartopo-mpi — the MPI driver of compensate's Monte Carlo (docs/monte-carlo.md, "MPI"): rank r of n computes the
// shard r + 1 of n with the library's shard code (the same sample indices and random streams as any run), rank 0
// gathers the raw samples (MPI_Gatherv of doubles: exact) and merges them with pipeline::merge_runs, so it writes the
// very files one `geartopo compensate` writes. An adaptive run (--adaptive-tolerance-um) goes batch by batch
// (pipeline::run_adaptive_batches): each batch of 100 split into contiguous blocks over the ranks, gathered on rank 0,
// which decides the stop (pipeline::adaptive_stability, or the --max-samples limit) and broadcasts it. Only this file
// and mpi_main.cpp see MPI; they are compiled only with -DGEARTOPO_MPI=ON.
//
// Failure without a hang: every rank enters exactly one agreement (MPI_Allreduce of the exit codes) before each
// gather, whatever happened on it — from complete() or the adaptive batch when its samples are done (0, or the code
// of what failed while they ran, e.g. a refused work estimate), from main when it failed before (its exit code, e.g.
// a bad scene or flag) or when it finished without a prediction (--samples 0). The ranks then all know the largest
// exit code and the lowest rank that failed; that rank prints its message, every rank exits with that code. Rank 0's
// own failures after a gather (merging what the ranks sent) reach the others through the stop broadcast of an
// adaptive batch; after the last gather only rank 0 works (it writes the files) and its failure is its own. MPI_Abort
// is not needed: no rank ever waits in a collective that another rank has left (a rank killed by a signal ends the
// job through mpirun).
#pragma once

#include "app/monte_carlo_flags.hpp"

#include <mpi.h>

#include <exception>
#include <optional>
#include <stdexcept>

namespace geartopo::app {

/// What the ranks agreed on in settle(): the largest exit code and the lowest rank with a non-zero one (−1: none).
struct RankAgreement {
  int exit_code = 0;
  int failing_rank = -1;
};

/// Thrown on a rank whose own work succeeded when settle() learnt that another rank failed: it exits with the agreed
/// code and prints nothing (the failing rank does).
struct OtherRankFailed : std::runtime_error {
  explicit OtherRankFailed(int exit_code);
  int exit_code;
};

class MpiMonteCarloDriver final : public MonteCarloDriver {
public:
  explicit MpiMonteCarloDriver(MPI_Comm comm);
  int rank() const { return rank_; }
  int size() const { return size_; }

  /// --shard is the driver's (refused) and every rank needs a sample (--samples ≥ ranks; adaptive: a sample of each
  /// batch, ranks ≤ 100).
  void check(const pipeline::MonteCarloOptions& options) const override;
  /// Shard rank + 1 of size (adaptive: 1 of 1, the driver splits each batch); threads: the CPUs this rank is bound to
  /// (sched_getaffinity; mpirun's --bind-to).
  pipeline::MonteCarloOptions this_process(const pipeline::MonteCarloOptions& options) const override;
  std::string split_hint() const override;
  bool writes_outputs() const override { return rank_ == 0; }
  /// settle(0); OtherRankFailed when a rank failed; then the gather. Rank 0: every rank's samples merged; the other
  /// ranks: std::nullopt.
  std::optional<pipeline::MonteCarloRun> complete(pipeline::MonteCarloRun local) const override;
  /// This rank's shard, or adaptive: its block of every batch up to --max-samples.
  long long samples_on_this_process(const pipeline::MonteCarloOptions& options) const override;
  /// A fixed number of samples: complete(this rank's shard). Adaptive: pipeline::run_adaptive_batches with each
  /// batch split over the ranks; before each batch's gather one agreement (a failure on a rank: its exception there,
  /// OtherRankFailed on the others); rank 0 merges and decides, MPI_Bcast of {stop, exit code}. Rank 0: the run.
  std::optional<pipeline::MonteCarloRun> run(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal,
                                             const pipeline::MonteCarloOptions& options) const override;

  /// The one collective every rank enters exactly once before the first gather (MPI_Allreduce of the exit codes).
  RankAgreement settle(int exit_code) const;
  /// True once this rank is past its last collective (or past the agreement that a rank failed).
  bool settled() const { return settled_; }
  /// The failure the ranks agreed on inside an adaptive run (std::nullopt: none): who prints, the exit code.
  const std::optional<RankAgreement>& agreed_failure() const { return agreed_failure_; }

private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  mutable bool settled_ = false;
  mutable std::optional<RankAgreement> agreed_failure_;

  RankAgreement allreduce_agreement(int exit_code) const;
  /// Every rank with its own code (0, or what `failure` is): on an agreed failure, `failure` rethrown on its rank,
  /// OtherRankFailed on the others.
  void agree_or_throw(int exit_code, const std::exception_ptr& failure) const;
};

/// geartopo's exit code for an exception: 2 bad usage (CLI::ValidationError), 1 anything else.
int exit_code_of(const std::exception_ptr& failure);

} // namespace geartopo::app
