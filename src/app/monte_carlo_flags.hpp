// geartopo — the Monte Carlo flags of compensate, run and report (--samples, --seed, --max-time-s, --shard i/n,
// --adaptive-tolerance-um, --max-samples, --probe-noise-um, --exact-samples) and the prediction files
// they write (docs/monte-carlo.md). A Slurm array job's task gets its --shard from SLURM_ARRAY_TASK_ID and
// SLURM_ARRAY_TASK_COUNT when the flag is not given (shard_from_slurm).
#pragma once

#include "geartopo/pipeline/monte_carlo.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace geartopo::app {

/// Longest Monte Carlo run (estimated wall time, s) compensate, run and report start unless --max-time-s says
/// otherwise: one day. Longer work belongs on several machines (compensate --shard i/n, then geartopo merge).
inline constexpr double kMaxMonteCarloSeconds = 86'400.0;

struct MonteCarloFlags {
  long long samples = 40;
  std::uint64_t seed = 1;
  std::string shard;   ///< --shard i/n; empty: not given (1/1, or the Slurm array task's: shard_from_slurm)
  bool shards = false; ///< the command writes partial results (--shard is one of its flags)
  double max_time_s = kMaxMonteCarloSeconds; ///< --max-time-s (MonteCarloWatch, work_estimates.hpp)
  double adaptive_tolerance_um = 0.0; ///< > 0: adaptive stop (JCGM 101 §7.9, docs/monte-carlo.md); --samples is then ignored
  long long max_samples = 10'000;     ///< the adaptive run's limit
  double probe_noise_um = 0.0;        ///< --probe-noise-um: σ of the probe noise each sample's gears are measured with
  bool exact_samples = false;         ///< --exact-samples: every sample simulated exactly (no first-order samples)
  bool samples_given = false;         ///< --samples was on the command line (an adaptive run does not use it)
  bool max_samples_given = false;     ///< --max-samples was on the command line (it only acts on an adaptive run)
  bool probe_noise_given = false;     ///< --probe-noise-um was on the command line (it only acts on a prediction)
};

/// The shard of a Slurm array task (docs/monte-carlo.md, "Slurm array job"): "i/n" with i = SLURM_ARRAY_TASK_ID −
/// SLURM_ARRAY_TASK_MIN + 1 and n = SLURM_ARRAY_TASK_COUNT, or std::nullopt outside an array job (the variables
/// unset). `getenv` reads a variable (std::getenv; tests give their own). Throws CLI::ValidationError naming --shard
/// for values that are not whole numbers or an array with gaps or steps (SLURM_ARRAY_TASK_MAX − MIN + 1 ≠ COUNT),
/// where the task number says nothing about its place among the tasks.
std::optional<std::string> shard_from_slurm(const std::function<const char*(const char*)>& getenv);

/// Who computes compensate's Monte Carlo samples. The default: this process, the shard its options name
/// (pipeline::run_monte_carlo). The MPI driver (geartopo-mpi, src/app/mpi_driver.cpp, built with -DGEARTOPO_MPI=ON)
/// gives every rank the shard rank + 1 of size and gathers all samples on rank 0; the libraries know nothing of MPI.
class MonteCarloDriver {
public:
  virtual ~MonteCarloDriver() = default;
  /// Checks the parsed options before any work (CLI::ValidationError naming the flag); the default checks nothing.
  virtual void check(const pipeline::MonteCarloOptions& options) const;
  /// The options of the samples this process computes (its shard, its threads); the default: `options` as they are.
  virtual pipeline::MonteCarloOptions this_process(const pipeline::MonteCarloOptions& options) const;
  /// Alternatives to name when a run's work estimate is refused (MonteCarloWatch).
  virtual std::string split_hint() const;
  /// Whether this process writes the command's files: the default yes; under MPI rank 0 only. The writer takes its
  /// output folder's lock before any work, so a second run into the folder is refused at once.
  virtual bool writes_outputs() const { return true; }
  /// This process's samples → the run the command writes: the default returns `local`; the MPI driver returns every
  /// rank's samples merged on rank 0 and std::nullopt on the other ranks (they write nothing and leave).
  virtual std::optional<pipeline::MonteCarloRun> complete(pipeline::MonteCarloRun local) const;
  /// How many samples this process computes at most with `options` (this_process's): the work estimate's count.
  /// The default: its shard's, or the adaptive limit --max-samples.
  virtual long long samples_on_this_process(const pipeline::MonteCarloOptions& options) const;
  /// The run the command writes, `options` from this_process(): the default is complete(run_monte_carlo(…)); the MPI
  /// driver runs an adaptive prediction batch by batch over the ranks, rank 0 deciding the stop.
  virtual std::optional<pipeline::MonteCarloRun> run(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal,
                                                     const pipeline::MonteCarloOptions& options) const;
};
/// The driver in use (the default one unless a program's main set another). Not thread-safe: set before parsing.
const MonteCarloDriver& monte_carlo_driver();
void set_monte_carlo_driver(const MonteCarloDriver* driver); ///< nullptr: the default; the driver must outlive its use

/// --samples, --seed, --max-time-s, --adaptive-tolerance-um, --max-samples and --probe-noise-um; --shard too when `shards` (a command that can write a partial result).
void add_monte_carlo_options(CLI::App* cmd, MonteCarloFlags& flags, bool shards);
/// Throws CLI::ValidationError naming --shard for a malformed i/n or more shards than samples, or what the
/// driver's check() refuses.
pipeline::MonteCarloOptions monte_carlo_options(const MonteCarloFlags& flags);
/// The options of a command that predicts in one go (run, report): nullopt for --samples 0.
std::optional<pipeline::MonteCarloOptions> prediction_options(const MonteCarloFlags& flags);
/// prediction.json and prediction.txt in `dir`.
void write_prediction(const std::filesystem::path& dir, const pipeline::MonteCarloSummary& s);

} // namespace geartopo::app
