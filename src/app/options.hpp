// geartopo — the command line's shared pieces: the scene's Workbench (built by the scene library) and the parsers of
// the options that several commands take.
#pragma once

#include "geartopo/files/output_folder.hpp"
#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace CLI {
class App;
class Validator;
}

namespace geartopo::app {

/// A number within [lo, hi] and finite: CLI::Range lets NaN through (every comparison with NaN is false), so
/// `--noise-um nan` or `--step nan` passed the check. Refuses NaN, ±inf and values outside the range (exit 2).
CLI::Validator finite_in(double lo, double hi);
/// The probe noise σ a fit divides by (--noise-um of compare, diagnose, plan, report): finite and within
/// [kMinProbeSigmaUm, kMaxProbeSigmaUm]; 1e-320 µm would make Σr²/σ² infinite in diagnosis.json and plan.json.
inline constexpr double kMinProbeSigmaUm = 1e-6, kMaxProbeSigmaUm = 1000.0;
CLI::Validator probe_sigma_um();
/// A path that is not empty: `--out ""` wrote into the current folder's root ("" / "file" is "file"; "" as a folder
/// was created as nothing) instead of being refused.
CLI::Validator non_empty_path();
/// A seed: a whole number of 0 … 2⁶⁴ − 1 written with digits only. CLI11 reads "-1" into an unsigned seed as
/// 2⁶⁴ − 1 and 2⁶⁴ as 0; both are refused (exit 2) naming the flag.
CLI::Validator seed_value();

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

/// `--json` of run, compare, diagnose and compensate: while it lives, the command's text on stdout is swallowed, and
/// emit() prints one JSON object instead (the same content as the command's main JSON file), so scripts read stdout
/// with a JSON parser. Warnings and errors stay on stderr. Without --json it does nothing.
class JsonSummary {
public:
  explicit JsonSummary(bool enabled);
  ~JsonSummary();
  JsonSummary(const JsonSummary&) = delete;
  JsonSummary& operator=(const JsonSummary&) = delete;
  void emit(const nlohmann::json& summary);

private:
  std::streambuf* saved_ = nullptr;
  std::unique_ptr<std::streambuf> sink_;
};

/// Closes a command's output folder (output_folder.hpp): removes what an earlier run wrote and this one did not, and
/// says so on stderr (unless --quiet).
void finish_output_folder(output::OutputFolder& folder);

/// The workbench's notes (what was chosen for the user, e.g. a wheel diameter) on stderr, unless --quiet.
void print_notes(const workbench::Workbench& wb);

using workbench::make_effects;
using workbench::Workbench;

/// When compensation made the gear worse — the largest |deviation| after is above the one before by more than
/// kWorseToleranceUm — the sentence to warn with (stderr and iso1328.json "warnings"), with the growth in µm and, when
/// the gear before was not already within kWorseToleranceUm of perfect, in percent; otherwise empty. E.g. the paper
/// method cancels a rotation that does not touch the flank (ε_yy, ε_ya) through the other axes and spoils the gear.
inline constexpr double kWorseToleranceUm = 0.01; ///< far below any tolerance, far above the simulation's rounding
std::string compensation_made_worse(double before_um, double after_um);

/// `--method paper` drives the wheel's pose to the nominal one at every pose, which would take away the design
/// motions that grind the drawing's helix modifications (docs/modifications.md): refused on such a scene
/// (CLI::ValidationError naming --method, exit 2). The flank and cycle methods correct towards the design.
void refuse_paper_on_a_designed_helix(const std::string& method, const workbench::Workbench& wb);

/// When the PREDICTED gear (Monte Carlo) is worse after compensation than before — a coarser median overall class, or
/// a median largest |deviation| above the whole 95 % interval before — the sentence to warn with; otherwise empty. The usual cause: corrections
/// smaller than the command resolution, rounded into steps (docs/monte-carlo.md).
std::string prediction_made_worse(const pipeline::MonteCarloSummary& prediction);

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
/// pipeline::MonteCarloOptions::on_sample_done. When the first sample is done: estimated wall time = the preparation's
/// measured time (on_prepared) + the first sample's × ⌈samples / threads⌉ (the threads draw samples one after another,
/// all of the same cost). Printed on a
/// terminal (not with --quiet); beyond max_seconds (--max-time-s, monte_carlo_flags.hpp) the run is refused —
/// CLI::ValidationError naming --samples with the estimate and the limit (exit 2, as --dense beyond the simulation's
/// bound), thrown from on_sample_done so that no further sample starts. Then the samples done and the time left on
/// the Progress line. Thread-safe.
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

/// "all" → {} (every tooth); "1,18" → {1, 18}. Throws CLI::ValidationError naming the option.
std::vector<int> parse_teeth(const std::string& text, int teeth);
/// "50x100" → (50, 100), at most grinding::kMaxPointsPerFlank points. Throws CLI::ValidationError.
std::pair<int, int> parse_grid_size(const std::string& text);

/// The Klingelnberg reader's options as flags of a command that reads measurements (docs/measurement-formats.md):
/// --mka-spacing roll-length|diameter, --mka-direction transverse|normal, --mka-signs raw|din.
void add_klingelnberg_options(CLI::App* cmd, measurement::KlingelnbergOptions& options);

/// `--measured FILE` (every format the readers tell apart by content, docs/measurement-formats.md) and the
/// Klingelnberg options: one text for compare, diagnose and plan (required) and run and report (optional: the
/// scene's measurement.measured when not given).
void add_measurement_options(CLI::App* cmd, std::string& file, measurement::KlingelnbergOptions& options,
                             bool required = true);
/// Throws CLI::ValidationError naming the first --mka-… flag on the command line when `file` is not a Klingelnberg
/// export (measurement::looks_like_klingelnberg): the flag would do nothing. Before the file is read.
void refuse_mka_flags_without_export(const std::string& file); ///< also when `file` is empty (nothing is read)
/// The measured points of `file` on the workbench's gear (measurement::read_any_measurement); the reader's warnings
/// (blocks of an export it did not use, …) on stderr. Throws InputError; refuse_mka_flags_without_export first.
std::vector<measurement::MeasuredPoint> read_measured_points(const workbench::Workbench& wb, const std::string& file,
                                                             const measurement::KlingelnbergOptions& options,
                                                             measurement::ReadCounts* counts = nullptr);

/// How a command that prints ISO 1328-1 values reports them (docs/iso1328.md): --iso-direction transverse|normal
/// (default transverse, the standard's), --helix-slope-sign helix-angle|rise-towards-plus-z (default helix-angle).
void add_iso_options(CLI::App* cmd, workbench::IsoOptions& options);

} // namespace geartopo::app
