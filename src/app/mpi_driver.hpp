// geartopo-mpi — the MPI driver of compensate's Monte Carlo (docs/monte-carlo.md, "MPI"): rank r of n computes the
// shard r + 1 of n with the library's shard code (the same sample indices and random streams as any run), rank 0
// gathers the raw samples (MPI_Gatherv of doubles: exact) and merges them with pipeline::merge_runs, so it writes the
// very files one `geartopo compensate` writes. Only this file and mpi_main.cpp see MPI; they are compiled only with
// -DGEARTOPO_MPI=ON.
//
// Failure without a hang: every rank enters exactly one collective before the gather, settle(exit code), whatever
// happened on it — from complete() when its samples are done (0), from main when it failed before (its exit code,
// e.g. a bad scene or flag) or when it finished without a prediction (--samples 0). The ranks then all know the
// largest exit code and the lowest rank that failed; that rank prints its message, every rank exits with that code.
// After the gather only rank 0 works (it writes the files); its failure is its own. MPI_Abort is not needed: no rank
// ever waits in a collective that another rank has left (a rank killed by a signal ends the job through mpirun).
#pragma once

#include "app/monte_carlo_flags.hpp"

#include <mpi.h>

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

  /// --shard is the driver's (refused), --adaptive-tolerance-um is refused (the stop needs every sample after each
  /// batch: docs/monte-carlo.md), and every rank needs a sample (--samples ≥ ranks).
  void check(const pipeline::MonteCarloOptions& options) const override;
  /// Shard rank + 1 of size; threads: the CPUs this rank is bound to (sched_getaffinity; mpirun's --bind-to).
  pipeline::MonteCarloOptions this_process(const pipeline::MonteCarloOptions& options) const override;
  std::string split_hint() const override;
  /// settle(0); OtherRankFailed when a rank failed; then the gather. Rank 0: every rank's samples merged; the other
  /// ranks: std::nullopt.
  std::optional<pipeline::MonteCarloRun> complete(pipeline::MonteCarloRun local) const override;

  /// The one collective every rank enters exactly once before the gather (MPI_Allreduce of the exit codes).
  RankAgreement settle(int exit_code) const;
  bool settled() const { return settled_; }

private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  mutable bool settled_ = false;
};

} // namespace geartopo::app
