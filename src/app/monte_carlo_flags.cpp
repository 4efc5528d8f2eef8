// The Monte Carlo flags that compensate, run and report share (monte_carlo_flags.hpp, docs/monte-carlo.md), the
// in-process driver, and the prediction files they write.
#include "app/monte_carlo_flags.hpp"

#include "app/messages.hpp"
#include "app/validators.hpp"

#include "geartopo/commands/limits.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/core/text_field.hpp"
#include "geartopo/report/prediction_report.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

namespace geartopo::app {

void add_monte_carlo_options(CLI::App* cmd, MonteCarloFlags& flags, bool shards) {
  cmd->add_option_function<long long>(
         "--samples",
         [&flags](const long long& v) {
           flags.samples = v;
           flags.samples_given = true;
         },
         fmt::format("Monte Carlo samples of the predicted after-state over all shards (default {}; 0: none; not with "
                     "--adaptive-tolerance-um)",
                     flags.samples))
      ->check(CLI::Range(0LL, commands::kMaxSamples));
  cmd->add_option("--seed", flags.seed, "Seed of the Monte Carlo draws (default 1): sample k depends on (seed, k) only")
      ->check(seed_value());
  cmd->add_option("--max-time-s", flags.max_time_s,
                  fmt::format("{} exceeds this wall time, s (default {:g}: one day)",
                              shards ? "Refuse a prediction whose estimate (after its first sample)"
                                     : "Refuse the job when the time spent plus the estimate of a simulation (after its "
                                       "first flank) or of the prediction (after its first sample)",
                              flags.max_time_s))
      ->check(finite_in(1e-3, 1e9));
  cmd->add_option("--adaptive-tolerance-um", flags.adaptive_tolerance_um,
                  "Adaptive Monte Carlo (JCGM 101 §7.9): batches of 100 samples until twice the standard deviation of "
                  "every µm quantity's median and 95 % interval ends over the batches is at most this (µm); replaces "
                  "--samples")
      ->check(finite_in(1e-6, 1e6)); // CLI::Range lets nan through, which turned adaptivity off
  cmd->add_option_function<long long>(
         "--max-samples",
         [&flags](const long long& v) {
           flags.max_samples = v;
           flags.max_samples_given = true;
         },
         fmt::format("The adaptive run's limit (default {}; with --adaptive-tolerance-um only)", flags.max_samples))
      ->check(CLI::Range(200LL, commands::kMaxSamples));
  cmd->add_option_function<double>(
         "--probe-noise-um",
         [&flags](const double& v) {
           flags.probe_noise_um = v;
           flags.probe_noise_given = true;
         },
         "Predict the gears as measured: each trace and grid point of every sample's gears plus Gaussian probe "
         "noise of this standard deviation, µm (the model of geartopo synth --noise-um; default 0: the true gears; "
         "not with --samples 0)")
      ->check(finite_in(0.0, 1000.0));
  cmd->add_flag("--exact-samples", flags.exact_samples,
                "Simulate every sample exactly (default: the nominal gears plus first-order sensitivities times each "
                "sample's draw, checked on 4 exact samples and exact when they differ by more than 0.05 µm)");
  if (!shards) return;
  flags.shards = true;
  cmd->add_option("--shard", flags.shard,
                  "i/n: compute only shard i of n (1 ≤ i ≤ n) and write its raw samples for `geartopo merge` (default 1/1; "
                  "in a Slurm array job SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT)");
}

std::optional<std::string> shard_from_slurm(const std::function<const char*(const char*)>& getenv) {
  const char* id = getenv("SLURM_ARRAY_TASK_ID");
  const char* count = getenv("SLURM_ARRAY_TASK_COUNT");
  if (id == nullptr || count == nullptr) return std::nullopt;
  const char* min = getenv("SLURM_ARRAY_TASK_MIN");
  const char* max = getenv("SLURM_ARRAY_TASK_MAX");
  const auto whole = [](const char* name, const char* text) {
    long long v = 0;
    if (text == nullptr || text::parse_number(std::string_view(text), v) != std::errc() || v < 0)
      throw CLI::ValidationError("--shard", fmt::format("not given, and {}='{}' is not a whole number ≥ 0", name,
                                                        text == nullptr ? "" : text::excerpt(text)));
    return v;
  };
  const long long i = whole("SLURM_ARRAY_TASK_ID", id), n = whole("SLURM_ARRAY_TASK_COUNT", count);
  // Slurm sets MIN and MAX with the array; without them the IDs are taken to run from 1 (--array=1-n).
  const long long lo = min != nullptr ? whole("SLURM_ARRAY_TASK_MIN", min) : 1;
  const long long hi = max != nullptr ? whole("SLURM_ARRAY_TASK_MAX", max) : lo + n - 1;
  if (hi - lo + 1 != n || i < lo || i > hi)
    throw CLI::ValidationError("--shard", fmt::format("not given, and the Slurm array (tasks {}..{}, {} of them, this one {}) "
                                                      "is not one contiguous range: give --shard i/n",
                                                      lo, hi, n, i));
  return fmt::format("{}/{}", i - lo + 1, n);
}

namespace {

// A flag that cannot act in the combination given is bad usage, not silently ignored (issue 31).
void refuse_flags_without_effect(const MonteCarloFlags& flags) {
  const bool adaptive = flags.adaptive_tolerance_um > 0.0;
  if (flags.samples == 0) { // no prediction at all, adaptive or not
    if (adaptive)
      throw CLI::ValidationError("--adaptive-tolerance-um", "has no effect with --samples 0: there is no prediction to "
                                                            "stop adaptively (leave --samples out, or this flag)");
    if (flags.probe_noise_given)
      throw CLI::ValidationError("--probe-noise-um", "has no effect with --samples 0: there is no prediction whose "
                                                     "gears it would measure");
  }
  if (flags.samples_given && adaptive)
    throw CLI::ValidationError("--samples", fmt::format("{} has no effect with --adaptive-tolerance-um: the adaptive run "
                                                        "takes batches of 100 until stable, at most --max-samples",
                                                        flags.samples));
  if (flags.max_samples_given && !adaptive)
    throw CLI::ValidationError("--max-samples", "has no effect without --adaptive-tolerance-um: it is the adaptive "
                                                "run's limit; a fixed run takes --samples N");
}

} // namespace

pipeline::MonteCarloOptions monte_carlo_options(const MonteCarloFlags& flags) {
  refuse_flags_without_effect(flags);
  pipeline::MonteCarloOptions o;
  o.samples = flags.samples;
  o.seed = flags.seed;
  o.sampling = flags.exact_samples ? pipeline::Sampling::Exact : pipeline::Sampling::Checked;
  std::string shard = flags.shard.empty() ? "1/1" : flags.shard;
  if (flags.shard.empty() && flags.shards && flags.samples > 0)
    if (const auto slurm = shard_from_slurm([](const char* name) { return std::getenv(name); })) {
      shard = *slurm;
      if (!quiet())
        say(fmt::format("geartopo: note: --shard {} from the Slurm array job (SLURM_ARRAY_TASK_ID {}, "
                        "SLURM_ARRAY_TASK_COUNT {})",
                        shard, std::getenv("SLURM_ARRAY_TASK_ID"), std::getenv("SLURM_ARRAY_TASK_COUNT")));
    }
  const auto slash = shard.find('/');
  int i = 0, n = 0;
  if (slash == std::string::npos || text::parse_number(std::string_view(shard).substr(0, slash), i) != std::errc() ||
      text::parse_number(std::string_view(shard).substr(slash + 1), n) != std::errc() || n < 1 || i < 1 || i > n)
    throw CLI::ValidationError("--shard", fmt::format("'{}' is not i/n with 1 ≤ i ≤ n", text::excerpt(shard)));
  if (flags.samples > 0 && n > flags.samples)
    throw CLI::ValidationError("--shard", fmt::format("{} shards for {} samples: every shard needs a sample", n, flags.samples));
  o.shard = i;
  o.shards = n;
  o.adaptive_tolerance_um = flags.adaptive_tolerance_um;
  o.adaptive_max_samples = flags.max_samples;
  o.probe_noise_um = flags.probe_noise_um;
  if (o.adaptive_tolerance_um > 0.0 && n > 1)
    throw CLI::ValidationError("--shard", "an adaptive run (--adaptive-tolerance-um) stops on all its samples: no shards");
  monte_carlo_driver().check(o);
  return o;
}

void MonteCarloDriver::check(const pipeline::MonteCarloOptions&) const {}

pipeline::MonteCarloOptions MonteCarloDriver::this_process(const pipeline::MonteCarloOptions& options) const {
  return options;
}

std::string MonteCarloDriver::split_hint() const { return "--shard i/n on several machines and geartopo merge"; }

std::optional<pipeline::MonteCarloRun> MonteCarloDriver::complete(pipeline::MonteCarloRun local) const { return local; }

long long MonteCarloDriver::samples_on_this_process(const pipeline::MonteCarloOptions& options) const {
  if (options.adaptive_tolerance_um > 0.0) return options.adaptive_max_samples;
  const auto [first, last] = pipeline::shard_range(options.samples, options.shard, options.shards);
  return last - first;
}

std::optional<pipeline::MonteCarloRun> MonteCarloDriver::run(const workbench::Workbench& wb,
                                                             const compensation::CorrectionTable& nominal,
                                                             const pipeline::MonteCarloOptions& options) const {
  return complete(pipeline::run_monte_carlo(wb, nominal, options));
}

namespace {
const MonteCarloDriver kInProcessDriver;
const MonteCarloDriver* g_monte_carlo_driver = &kInProcessDriver;
} // namespace

const MonteCarloDriver& monte_carlo_driver() { return *g_monte_carlo_driver; }

void set_monte_carlo_driver(const MonteCarloDriver* driver) {
  g_monte_carlo_driver = driver != nullptr ? driver : &kInProcessDriver;
}

std::optional<pipeline::MonteCarloOptions> prediction_options(const MonteCarloFlags& flags) {
  refuse_flags_without_effect(flags);
  if (flags.samples == 0) return std::nullopt;
  return monte_carlo_options(flags);
}

void write_prediction(const std::filesystem::path& dir, const pipeline::MonteCarloSummary& s) {
  output::write_text_atomically(dir / "prediction.json", report::prediction_json(s).dump(2) + "\n");
  std::string text;
  for (const auto& l : report::prediction_lines(s)) text += l + "\n";
  output::write_text_atomically(dir / "prediction.txt", text);
}

} // namespace geartopo::app
