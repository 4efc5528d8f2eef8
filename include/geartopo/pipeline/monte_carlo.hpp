// geartopo — the predicted after-state of a compensation as a distribution (docs/monte-carlo.md), GUM Supplement 1
// style: the corrections come from the NOMINAL model (the scene); the machine that grinds is drawn within the scene's
// uncertainties (machine.uncertainty, repeatability, resolution). Sample k:
//   1. the true error map: every component of the scene's map plus z·u, one z ~ N(0, 1) per component (u its standard
//      uncertainty: the table's u_ column at the position, else the scene's constant; a calibration offset, fully
//      correlated along the axis: ErrorSource::drawn);
//   2. gear 1 ("before"): the true machine grinds without corrections; each stroke's X, Y, Z, A, C are off by a draw
//      of N(0, σ²) (σ the axis repeatability), constant over the stroke;
//   3. gear 2 ("after"): the same true machine grinds with the nominal corrections rounded to the command resolution
//      and fresh repeatability draws per stroke;
//   (effects whose values carry uncertainties, e.g. from a diagnosis fit, are drawn within them for both gears;)
//   4. both gears are evaluated per ISO 1328-1 (workbench::evaluate_iso) and reduced to named quantities.
// A draw is small (µm, µrad), so by default a sample's gears are the nominal gears plus first-order sensitivities times
// the draw (topology_sensitivities.hpp; the rounding is in the nominal after-gear, exactly), checked on a few exact
// samples each run and replaced by exact samples when first order is not good enough (Sampling).
// Every draw of sample k comes from a generator seeded by (seed, k) alone, so sample k is the same whatever the
// thread count or shard: shards merged equal one run bit for bit. The summary of each quantity is its median and
// its 95 % probabilistically symmetric coverage interval (JCGM 101:2008 §7.7).
// Units: mm and rad inside; quantity names carry theirs (_um, _class).
#pragma once

#include "geartopo/compensation/correction_table.hpp"
#include "geartopo/core/limits.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/machine/axis_pose.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace geartopo::pipeline {

/// How a sample's two gears are computed (docs/monte-carlo.md, "Linear samples").
enum class Sampling {
  Checked, ///< nominal + first-order sensitivities × the draw (topology_sensitivities.hpp) when kCheckSamples exact samples
           ///< agree with their linear twins within kLinearAgreementUm in every µm quantity; else exact
  Exact,   ///< every sample simulated exactly (the exact envelope of the drawn machine)
  Linear,  ///< first order without the check (tests, comparisons)
};
/// Exact samples compared with their linear twins: samples 0 … kCheckSamples − 1 of the run's seed, whatever the shard or
/// batch, so every shard, rank and batch takes the same decision.
inline constexpr int kCheckSamples = 4;
/// Largest |exact − linear| of any µm quantity (ISO values, largest |deviation|, thickness, rotation; both gears) of the
/// checked samples that lets the run use linear samples: half the 0.1 µm step ISO 1328-1:2013 rounds its tolerances to
/// below 5 µm (docs/iso1328.md), and a tenth of the narrowest 95 % interval of the default scene's ISO values. The
/// largest difference at any point is reported too: next to the steps of corrections rounded to a coarse resolution it
/// is larger at a few points (the deepest cut moves across a step), which the quantities do not feel.
inline constexpr double kLinearAgreementUm = 0.05;

/// A source of the after-state's scatter or error that the decomposition switches off one at a time (linear samples
/// only): the map's uncertainty (the 43 components' draws), the strokes' repeatability, the rounding of the
/// corrections to machine.resolution, the effects' uncertain values, the probe noise.
inline const std::vector<std::string>& limit_sources() {
  static const std::vector<std::string> names{"map_uncertainty", "repeatability", "resolution_rounding",
                                              "effect_uncertainty", "probe_noise"};
  return names;
}

/// The most samples a run takes: every front end's bound (commands::kMaxSamples), checked again by run_monte_carlo —
/// 10⁹ ended in std::bad_alloc.
inline constexpr long long kMaxMonteCarloSamples = limits::kMaxSamples; // core/limits.hpp

struct MonteCarloOptions {
  long long samples = 200;  ///< M, over all shards: 1 … kMaxMonteCarloSamples
  std::uint64_t seed = 1;
  int shard = 1, shards = 1; ///< this run computes shard `shard` of `shards` (1-based): a contiguous block of samples
  int threads = 0;           ///< 0: all hardware threads (results do not depend on it)
  workbench::IsoOptions iso; ///< how the ISO 1328-1 values are reported (direction, f_Hβ sign)
  /// Called after each sample of this run with (samples done, samples in this run), from the worker threads: must be
  /// thread-safe and cheap. For progress and work estimates only; the samples do not depend on it. An exception it
  /// throws (a work estimate beyond its limit) stops the samples not yet started and leaves run_monte_carlo.
  std::function<void(long long done, long long total)> on_sample_done;
  /// > 0: adaptive (JCGM 101:2008 §7.9, adapted: docs/monte-carlo.md): `samples` is ignored; batches of
  /// adaptive_batch samples run until twice the standard deviation of the mean over the batches of every µm
  /// quantity's median and 95 % interval ends (before and after) is at most this tolerance (µm), or
  /// adaptive_max_samples are reached. Needs shards = 1. The result equals a plain run of the samples it stopped at.
  double adaptive_tolerance_um = 0.0;
  long long adaptive_batch = 100;
  long long adaptive_max_samples = 10'000;
  /// > 0: every sample's gears (before and after) are "measured" before their evaluation: each point of every flank's
  /// profile trace, helix trace and grid plus probe_noise_um times a standard normal deviate
  /// (diagnosis::add_probe_noise, the model of `geartopo synth`), drawn from a stream of (seed, k) of its own, so
  /// the machine's draws of sample k do not depend on it. 0: the true gears (no draw at all).
  double probe_noise_um = 0.0;
  Sampling sampling = Sampling::Checked;
  /// Called once the run is prepared (sensitivities computed, exact samples checked), before the first sample starts:
  /// the work estimate times the samples from here. Not called when there is nothing to prepare.
  std::function<void()> on_prepared;
};

/// The gear quantities one simulated (or measured) gear reduces to, by name with unit: "F_beta_um", "F_beta_class",
/// …, "overall_class", "largest_abs_um", "thickness_um", "rotation_um" — ISO values as |worst value| (slopes too: the
/// class compares |value|, and the worst flank's sign would split a band in two) — only what the evaluation provides (pitch
/// needs all teeth; classes need the range of validity). thickness_um: mean over teeth of the mean grid deviation of
/// the left plus the right flank (plus material: thicker); rotation_um: mean over teeth of (left − right)/2 (a rigid
/// rotation of the gear, positive when the left flanks gain material).
struct GearQuantities {
  std::vector<std::string> names;
  std::vector<double> values;
};
GearQuantities gear_quantities(const workbench::IsoResult& iso, const std::vector<grinding::FlankTopology>& topo);

struct MonteCarloSample {
  long long index = 0;        ///< k, 0-based over all shards
  std::vector<double> before; ///< in the order of MonteCarloRun::names
  std::vector<double> after;
  /// The after-gear with one source switched off, per MonteCarloRun::without (linear samples only; same draws).
  std::vector<std::vector<double>> after_without;
};

/// How the samples were computed and how well first order held on the checked samples.
struct SamplingReport {
  std::string method = "exact"; ///< "linear" or "exact"
  /// "checked" (linear, the check passed), "check failed" (exact: the check did not pass), "forced" (exact asked for),
  /// "unchecked" (linear without check), "" (not recorded: a file written before it was)
  std::string reason;
  int checked_samples = 0;             ///< exact samples compared with their linear twins
  double largest_point_difference_um = 0.0;    ///< max |exact − linear| over their points (both gears)
  double largest_quantity_difference_um = 0.0; ///< max |exact − linear| over their µm quantities (both gears)
  bool operator==(const SamplingReport&) const = default;
};

/// Raw samples of one shard (or of several merged): what a merge needs to recompute the same order statistics.
struct MonteCarloRun {
  long long samples_total = 0;
  std::uint64_t seed = 0;
  workbench::IsoOptions iso;  ///< how the samples' ISO values were reported (MonteCarloOptions::iso)
  double probe_noise_um = 0.0; ///< MonteCarloOptions::probe_noise_um
  std::vector<std::string> names;
  SamplingReport sampling;
  std::vector<std::string> without; ///< the sources switched off, one per MonteCarloSample::after_without (limit_sources names)
  std::vector<MonteCarloSample> samples; ///< increasing index
  /// What the samples were computed from (scene_fingerprint); "" when not recorded (computed in memory, or a file
  /// written before it was). Shards merge only with the same fingerprint.
  std::string scene_fingerprint;
  std::string gear;   ///< gear_record of the gear the samples are of; "" when not recorded (a file written before)
  std::string source; ///< the file it was read from (read_run_csv), for messages; "" when computed
  /// read_run_csv: the line of each setting by its key ("seed", "scene_fingerprint", …) and of the "header", for
  /// merge_runs' refusals (file:line: field); empty when computed.
  std::map<std::string, int> lines;
};

/// Why `value` cannot be quantity `name` of a run (an unknown name; not finite; a class not a whole number of ISO
/// 1328-1's range; a negative magnitude; beyond ±kMaxQuantityUm), or nullopt when it can: the check read_run_csv
/// makes of every shard value, for other readers of predictions (report::read_prediction_json).
std::optional<std::string> quantity_value_refusal(const std::string& name, double value);

/// The gear a prediction is of, as prediction.json and a shard record it and `evaluate --prediction` compares it:
/// "teeth=35 normal_module_mm=14 normal_pressure_angle_deg=20 helix_angle_deg=30 profile_shift=0.274
/// face_width_mm=150" (scene keys, 9 significant digits).
std::string gear_record(const gears::GearSpec& spec);

/// The scene a Monte Carlo run samples, as a fingerprint: FNV-1a (64 bit, 16 hex digits) of the scene file's bytes,
/// of each error table it names (in scene order) and of `options` (the command's settings that change the samples,
/// e.g. "method=flank step_mm=5"). Shards of one run share it; a shard computed from an edited scene or table, or
/// with other corrections, does not. Throws InputError when a file cannot be read.
std::string scene_fingerprint(const workbench::Workbench& wb, const std::string& options);

/// Largest |value| of a µm quantity a partial result may hold (read_run_csv): 10 mm. A ground gear's ISO values and
/// deviations are µm to tens of µm; flanks within ±grinding::kMaxDeviationUm (1000 µm, the most any measurement
/// reader accepts) give ISO values of a few thousand µm at most (a range is twice the largest deviation, runout
/// 1/(2 sin α_n) times a thickness change).
inline constexpr double kMaxQuantityUm = 10'000.0;

/// The corrections a controller applies, at the scale of the table's rows: the controller rounds the setpoint, command
/// plus correction, to the axis' command resolution (X, Y, Z mm; A, C rad; 0 leaves the axis as it is), and each row
/// gets that rounding error averaged over its stretch of the stroke (midpoint to midpoint of its neighbours), with the
/// command moving as the rows' `machine_axes` say. An axis standing still along the stroke (X, Y, A of a plain gear)
/// is rounded to the nearest multiple, round(δq/q)·q; an axis the stroke sweeps through n units (C, Z) errs by at
/// most q/(8n) on average — a sawtooth of sub-µm period in Z that no wheel pass resolves (docs/compensation.md,
/// "Command resolution").
compensation::CorrectionTable rounded_to_resolution(const compensation::CorrectionTable& table,
                                                    const machine::Vector5d& resolution);

/// Each stroke's scatter (ISO 230-2 repeatability, one standard deviation s_a per axis, scene `machine.repeatability`):
/// for every space of `spaces` in increasing order, the command offsets of X, Y, Z (mm), A, C (rad), each s_a times a
/// draw of `standard_normal`, in that order — the draw of every Monte Carlo sample (gear 1, then gear 2), of `geartopo
/// synth --stroke-scatter` and of the closed-loop test. The offsets are constant over the stroke.
std::map<int, machine::Vector5d> draw_stroke_offsets(const std::set<int>& spaces, const machine::Vector5d& repeatability_sd,
                                                     const std::function<double()>& standard_normal);

/// `base` with each row's correction plus its space's offset: the corrections a stroke actually receives. Throws
/// std::invalid_argument for a row whose space has no offset.
compensation::CorrectionTable with_stroke_offsets(const compensation::CorrectionTable& base,
                                                  const std::map<int, machine::Vector5d>& offsets);

/// First and one-past-last sample of a shard (1-based shard of shards): contiguous blocks of ⌊M/n⌋ or ⌈M/n⌉.
std::pair<long long, long long> shard_range(long long samples, int shard, int shards);

/// Runs samples [first, last) of a run of options.samples (0 ≤ first ≤ last ≤ samples; the adaptive fields and the
/// shard are ignored): sample k depends on (seed, k) alone, so any block equals the same samples of any run. The
/// result's samples_total is options.samples. The batches of an adaptive run and the MPI driver's blocks are such
/// ranges. Throws std::invalid_argument for a range outside [0, samples].
MonteCarloRun run_monte_carlo_samples(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal,
                                      const MonteCarloOptions& options, long long first, long long last);

/// The adaptive loop (JCGM 101:2008 §7.9, adapted: docs/monte-carlo.md) with the batches computed by the caller, for
/// a process that computes a batch with others (the MPI driver). Batch h = 1, 2, … is samples [(h − 1)·B, h·B),
/// B = options.adaptive_batch: `run_batch(first, last)` returns all of them on the process that decides and
/// std::nullopt on any other; the deciding process appends them and, from h = 2 on, asks adaptive_stability;
/// the deciding process stops when stable or when one more batch would pass options.adaptive_max_samples, and
/// `agree(stop)` returns its stop on every process (the identity in one process). Returns the run (samples_total
/// h·B) on the deciding process, std::nullopt on the others. Throws std::invalid_argument for bad adaptive options.
std::optional<MonteCarloRun> run_adaptive_batches(
    const MonteCarloOptions& options, const std::function<std::optional<MonteCarloRun>(long long first, long long last)>& run_batch,
    const std::function<bool(bool stop)>& agree);

/// Runs the samples of options' shard. `nominal` holds the corrections computed on the scene's model (they are
/// rounded here). Throws std::invalid_argument for bad options.
MonteCarloRun run_monte_carlo(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal,
                              const MonteCarloOptions& options);

/// How stable the summary of the first h·batch samples of a run is (JCGM 101:2008 §7.9.4, adapted): for each µm
/// quantity (name ending in "_um"), before and after, the median and the 95 % interval ends of each of the h batches
/// (coverage_band), and s = √(Σ_r (x_r − x̄)² / (h(h − 1))), the standard deviation of their mean. `worst_two_s_um` is
/// the largest 2s, `worst` names it ("after.F_p_um high"); stable when h ≥ 2 and worst_two_s_um ≤ tolerance_um.
struct AdaptiveStability {
  long long batches = 0;
  double worst_two_s_um = 0.0;
  std::string worst;
  bool stable = false;
};
/// Throws std::invalid_argument unless the run holds samples 0..h·batch − 1 (h ≥ 1) in order.
AdaptiveStability adaptive_stability(const MonteCarloRun& run, long long batch, double tolerance_um);

/// Partials of one run (same seed, sample count, ISO options, probe noise, names and scene fingerprint) → one run with
/// every sample once. Throws std::invalid_argument naming the parts (their files when read from files) and what does
/// not match, or a sample given twice.
MonteCarloRun merge_runs(std::vector<MonteCarloRun> parts);

/// Median and 95 % probabilistically symmetric coverage interval of M values (JCGM 101:2008 §7.7: sorted values
/// y_(1..M), q = pM rounded to an integer, r = (M − q)/2 rounded up, interval [y_(r), y_(r+q)], r ≥ 1).
struct Band {
  double median = 0.0, low = 0.0, high = 0.0;
};
Band coverage_band(std::vector<double> values, double coverage = 0.95);

struct MonteCarloSummary {
  long long samples = 0;
  std::uint64_t seed = 0;
  /// The ISO options the samples were evaluated with; std::nullopt: not recorded (a prediction.json written before
  /// they were, read by report::read_prediction_json).
  std::optional<workbench::IsoOptions> iso;
  double probe_noise_um = 0.0; ///< σ of the probe noise the samples were "measured" with (µm; 0: the true gears)
  std::string gear;            ///< MonteCarloRun::gear
  std::vector<std::string> names;
  std::vector<Band> before, after; ///< per name
  SamplingReport sampling;
  std::vector<std::string> without;           ///< sources switched off (MonteCarloRun::without)
  std::vector<std::vector<Band>> after_without; ///< per source, per name
  /// Index of a name, or -1.
  int find(const std::string& name) const;
};

/// Which source sets the class after compensation (docs/monte-carlo.md, "What limits the gear after"): for every
/// source switched off, the after-gear's median overall class, and the ISO quantity that sets the class with all
/// sources on (the largest median class; among equals the first in the evaluation's order) with its median with and
/// without the source. The dominant source is the one whose absence
/// lowers the median overall class most; among equals the one that lowers the limiting quantity's median most.
struct SourceEffect {
  std::string source;
  double overall_class = 0.0;       ///< median overall class after, without the source
  double limiting_median_um = 0.0;  ///< the limiting quantity's median after, without the source
};
struct AfterLimit {
  bool measured = false;           ///< false: exact samples (no decomposition) or no class
  double overall_class = 0.0;      ///< median overall class after, all sources on
  std::string limiting_quantity;   ///< e.g. "f_p_um"
  double limiting_median_um = 0.0; ///< its median after, all sources on
  std::vector<SourceEffect> without; ///< per source switched off
  std::string dominant;            ///< limit_sources name; empty when not measured
};
AfterLimit after_limit(const MonteCarloSummary& summary);
/// Throws std::invalid_argument unless every sample 0..M−1 is present.
MonteCarloSummary summarise(const MonteCarloRun& run);

/// Partial result file (CSV, doubles in shortest round-trip form): comment lines "# samples_total: M",
/// "# seed: S", "# iso_direction: transverse", "# helix_slope_sign: helix-angle", "# probe_noise_um: 0", "# sampling:
/// linear", "# sampling_reason: checked", "# linear_check_samples: 4", "# linear_check_points_um: …",
/// "# linear_check_quantities_um: …", "# scene_fingerprint: …" (when recorded), then "sample,before.<name>,…,after.<name>,…[,without_<source>.<name>,…]", one row
/// per sample.
void write_run_csv(const std::filesystem::path& file, const MonteCarloRun& run);
/// Throws InputError at the file's line, column and field, saying what is allowed, for anything compensate does not
/// write: a seed outside 0 … 2⁶⁴ − 1, a quantity name geartopo does not write or one given twice, a sample number
/// outside the run or not increasing, a value that is not finite, a class that is not a whole number of 1 … 11 (12:
/// worse than class 11), an ISO value or largest |deviation| below 0 (they are magnitudes), any µm value beyond
/// ±kMaxQuantityUm. A file without the iso_direction, helix_slope_sign or probe_noise_um lines (written before they
/// were) reads as transverse, helix-angle and 0: what compensate computed then; without the sampling lines as exact
/// samples, reason not recorded; without scene_fingerprint as not recorded.
MonteCarloRun read_run_csv(const std::filesystem::path& file);

} // namespace geartopo::pipeline
