// geartopo-mpi — the MPI driver of compensate's Monte Carlo: shards per rank (or blocks of each adaptive batch), one
// agreement before each gather, the gather on rank 0 (mpi_driver.hpp). Units: none of its own (the samples are the library's µm and class quantities, moved as doubles).
#include "app/mpi_driver.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <sched.h>

#include <array>
#include <bit>
#include <climits>
#include <cstdint>
#include <string>
#include <vector>

namespace geartopo::app {
namespace {

/// What a rank sends ahead of its samples: the lengths of its two buffers and the run's identity (merge_runs
/// compares seed, sample count, ISO options, probe noise and names, so a rank that computed something else is refused).
enum RankHeaderField {
  kRankNamesChars,
  kRankSampleDoubles,
  kRankSamplesTotal,
  kRankSeed,
  kRankIsoDirection,
  kRankHelixSlopeSign,
  kRankProbeNoiseBits, ///< the double's bits: exact
  kRankHeaderFields
};
using RankHeader = std::array<unsigned long long, kRankHeaderFields>;

/// Number of CPUs this process may run on (mpirun binds each rank: --bind-to core, --map-by …:PE=t, --bind-to none).
int cpus_bound_to_this_rank() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return 0; // unknown: parallel_for takes all hardware threads
  return CPU_COUNT(&set);
}

int mpi_count_or_throw(std::size_t n, const char* what) {
  if (n > static_cast<std::size_t>(INT_MAX))
    throw std::invalid_argument(fmt::format("{} of one rank's samples: {} elements exceed MPI's int count; use more ranks", what, n));
  return static_cast<int>(n);
}

/// The first line of the names text: how the rank's samples were computed and the sources its variants leave out,
/// '|'-separated, the doubles in their shortest round-trip form (exact).
std::string sampling_line(const pipeline::MonteCarloRun& run) {
  const auto& r = run.sampling;
  return fmt::format("{}|{}|{}|{}|{}|{}", r.method, r.reason, r.checked_samples, r.largest_point_difference_um,
                     r.largest_quantity_difference_um, fmt::join(run.without, ","));
}

void read_sampling_line(int rank, const std::string& line, pipeline::MonteCarloRun& run) {
  std::vector<std::string> f;
  for (std::size_t start = 0;;) {
    const std::size_t bar = line.find('|', start);
    f.push_back(line.substr(start, bar == std::string::npos ? std::string::npos : bar - start));
    if (bar == std::string::npos) break;
    start = bar + 1;
  }
  if (f.size() != 6) throw std::invalid_argument(fmt::format("MPI rank {} sent no sampling line", rank));
  run.sampling.method = f[0];
  run.sampling.reason = f[1];
  run.sampling.checked_samples = std::stoi(f[2]);
  run.sampling.largest_point_difference_um = std::stod(f[3]);
  run.sampling.largest_quantity_difference_um = std::stod(f[4]);
  for (std::size_t start = 0; start < f[5].size();) {
    const std::size_t end = std::min(f[5].find(',', start), f[5].size());
    run.without.push_back(f[5].substr(start, end - start));
    start = end + 1;
  }
}

/// Rank r's part as a run: the sampling line, then the names, split at '\n'; rows of (index, before…, after…, each
/// variant's after…).
pipeline::MonteCarloRun rank_part_as_run(int rank, const RankHeader& header, const char* names, const double* values) {
  pipeline::MonteCarloRun part;
  part.samples_total = static_cast<long long>(header[kRankSamplesTotal]);
  part.seed = header[kRankSeed];
  part.iso.direction = static_cast<evaluation::IsoDirection>(header[kRankIsoDirection]);
  part.iso.helix_slope_sign = static_cast<evaluation::HelixSlopeSign>(header[kRankHelixSlopeSign]);
  part.probe_noise_um = std::bit_cast<double>(static_cast<std::uint64_t>(header[kRankProbeNoiseBits]));
  const std::string joined(names, header[kRankNamesChars]);
  bool first_line = true;
  for (std::size_t start = 0; start < joined.size();) {
    const std::size_t end = std::min(joined.find('\n', start), joined.size());
    if (first_line) read_sampling_line(rank, joined.substr(start, end - start), part);
    else part.names.push_back(joined.substr(start, end - start));
    first_line = false;
    start = end + 1;
  }
  const std::size_t n = part.names.size(), groups = 2 + part.without.size();
  const std::size_t width = 1 + groups * n, count = header[kRankSampleDoubles];
  if (count % width != 0)
    throw std::invalid_argument(fmt::format("MPI rank {} sent {} values, not whole samples of {} quantities", rank, count,
                                            part.names.size()));
  for (std::size_t row = 0; row < count / width; ++row) {
    const double* v = values + row * width;
    pipeline::MonteCarloSample s;
    s.index = static_cast<long long>(v[0]);
    s.before.assign(v + 1, v + 1 + n);
    s.after.assign(v + 1 + n, v + 1 + 2 * n);
    for (std::size_t g = 2; g < groups; ++g) s.after_without.emplace_back(v + 1 + g * n, v + 1 + (g + 1) * n);
    part.samples.push_back(std::move(s));
  }
  return part;
}

/// One rank's samples as MPI sends them: the names joined by '\n', rows of (index, before…, after…), the header.
struct PackedRun {
  std::string names;
  std::vector<double> values;
  RankHeader header{};
};

/// Everything that can fail on this rank alone (the counts beyond MPI's int), before any collective.
PackedRun pack(const pipeline::MonteCarloRun& local) {
  PackedRun p;
  p.names = sampling_line(local);
  for (const auto& n : local.names) p.names += "\n" + n;
  p.values.reserve(local.samples.size() * (1 + (2 + local.without.size()) * local.names.size()));
  for (const auto& s : local.samples) {
    p.values.push_back(static_cast<double>(s.index)); // exact: indices < 2⁵³ (--samples ≤ 10⁶)
    p.values.insert(p.values.end(), s.before.begin(), s.before.end());
    p.values.insert(p.values.end(), s.after.begin(), s.after.end());
    for (const auto& w : s.after_without) p.values.insert(p.values.end(), w.begin(), w.end());
  }
  p.header = {static_cast<unsigned long long>(mpi_count_or_throw(p.names.size(), "the names")),
              static_cast<unsigned long long>(mpi_count_or_throw(p.values.size(), "the values")),
              static_cast<unsigned long long>(local.samples_total),
              local.seed,
              static_cast<unsigned long long>(local.iso.direction),
              static_cast<unsigned long long>(local.iso.helix_slope_sign),
              std::bit_cast<std::uint64_t>(local.probe_noise_um)};
  return p;
}

/// Collectives only: every rank's part on rank 0 (in rank order), std::nullopt on the others.
std::optional<std::vector<pipeline::MonteCarloRun>> gather_parts(const PackedRun& mine, int rank, int size, MPI_Comm comm) {
  std::vector<RankHeader> headers(rank == 0 ? static_cast<std::size_t>(size) : 0);
  MPI_Gather(mine.header.data(), kRankHeaderFields, MPI_UNSIGNED_LONG_LONG, headers.data(), kRankHeaderFields,
             MPI_UNSIGNED_LONG_LONG, 0, comm);
  // Counts and displacements of the two gathers (rank 0 only). The totals fit an int: --samples ≤ 10⁶ (CLI range),
  // each 1 + (2 + variants: at most 5) × (quantities: 22 on the default scene) doubles, 1.6·10⁸ of 2.1·10⁹.
  std::vector<int> names_counts, names_displs, values_counts, values_displs;
  long long names_total = 0, values_total = 0;
  for (const auto& h : headers) {
    names_displs.push_back(static_cast<int>(names_total));
    names_counts.push_back(static_cast<int>(h[kRankNamesChars]));
    values_displs.push_back(static_cast<int>(values_total));
    values_counts.push_back(static_cast<int>(h[kRankSampleDoubles]));
    names_total += static_cast<long long>(h[kRankNamesChars]);
    values_total += static_cast<long long>(h[kRankSampleDoubles]);
  }
  std::vector<char> all_names(static_cast<std::size_t>(names_total));
  std::vector<double> all_values(static_cast<std::size_t>(values_total));
  MPI_Gatherv(mine.names.data(), static_cast<int>(mine.header[kRankNamesChars]), MPI_CHAR, all_names.data(),
              names_counts.data(), names_displs.data(), MPI_CHAR, 0, comm);
  MPI_Gatherv(mine.values.data(), static_cast<int>(mine.header[kRankSampleDoubles]), MPI_DOUBLE, all_values.data(),
              values_counts.data(), values_displs.data(), MPI_DOUBLE, 0, comm);
  if (rank != 0) return std::nullopt;
  std::vector<pipeline::MonteCarloRun> parts;
  for (int r = 0; r < size; ++r) {
    const auto i = static_cast<std::size_t>(r);
    parts.push_back(rank_part_as_run(r, headers[i], all_names.data() + names_displs[i], all_values.data() + values_displs[i]));
  }
  return parts;
}

} // namespace

int exit_code_of(const std::exception_ptr& failure) {
  try {
    std::rethrow_exception(failure);
  } catch (const CLI::ValidationError&) {
    return 2;
  } catch (...) {
    return 1;
  }
}

OtherRankFailed::OtherRankFailed(int code) : std::runtime_error("another MPI rank failed"), exit_code(code) {}

MpiMonteCarloDriver::MpiMonteCarloDriver(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

void MpiMonteCarloDriver::check(const pipeline::MonteCarloOptions& options) const {
  if (options.shards != 1)
    throw CLI::ValidationError("--shard", "geartopo-mpi gives rank r of n the shard r+1/n: leave --shard out");
  // No prediction: nothing to scatter over the ranks, each would compute and rank 0 write the nominal result alone
  // (docs/monte-carlo.md: more ranks than --samples are refused).
  if (options.samples <= 0)
    throw CLI::ValidationError("--samples", fmt::format("0 samples over {} MPI ranks: geartopo-mpi scatters the Monte Carlo "
                                                        "samples; without a prediction run geartopo compensate --samples 0",
                                                        size_));
  if (options.adaptive_tolerance_um > 0.0) {
    if (options.adaptive_batch < size_)
      throw CLI::ValidationError("--adaptive-tolerance-um",
                                 fmt::format("{} MPI ranks for adaptive batches of {} samples: every rank needs a sample of "
                                             "each batch", size_, options.adaptive_batch));
    return;
  }
  if (options.samples < size_)
    throw CLI::ValidationError("--samples", fmt::format("{} MPI ranks for {} samples: every rank needs a sample", size_,
                                                        options.samples));
}

pipeline::MonteCarloOptions MpiMonteCarloDriver::this_process(const pipeline::MonteCarloOptions& options) const {
  pipeline::MonteCarloOptions o = options;
  if (o.adaptive_tolerance_um <= 0.0) { // adaptive: one run of batches, each split by run()
    o.shard = rank_ + 1;
    o.shards = size_;
  }
  if (o.threads <= 0) o.threads = cpus_bound_to_this_rank();
  return o;
}

long long MpiMonteCarloDriver::samples_on_this_process(const pipeline::MonteCarloOptions& options) const {
  if (options.adaptive_tolerance_um <= 0.0) return MonteCarloDriver::samples_on_this_process(options);
  const auto [first, last] = pipeline::shard_range(options.adaptive_batch, rank_ + 1, size_);
  return options.adaptive_max_samples / options.adaptive_batch * (last - first);
}

std::string MpiMonteCarloDriver::split_hint() const { return "more MPI ranks (mpirun -n) on more machines"; }

RankAgreement MpiMonteCarloDriver::settle(int exit_code) const {
  if (settled_) throw std::logic_error("MpiMonteCarloDriver::settle called twice on one rank");
  settled_ = true;
  return allreduce_agreement(exit_code);
}

RankAgreement MpiMonteCarloDriver::allreduce_agreement(int exit_code) const {
  // {largest exit code, size − lowest failing rank}: one MPI_MAX reduction gives both.
  const std::array<int, 2> mine{exit_code, exit_code != 0 ? size_ - rank_ : 0};
  std::array<int, 2> all{};
  MPI_Allreduce(mine.data(), all.data(), 2, MPI_INT, MPI_MAX, comm_);
  return {all[0], all[1] > 0 ? size_ - all[1] : -1};
}

std::optional<pipeline::MonteCarloRun> MpiMonteCarloDriver::complete(pipeline::MonteCarloRun local) const {
  const PackedRun packed = pack(local); // everything that can fail on this rank alone happens before settle()
  if (const RankAgreement agreed = settle(0); agreed.exit_code != 0) throw OtherRankFailed(agreed.exit_code);
  auto parts = gather_parts(packed, rank_, size_, comm_);
  if (!parts) return std::nullopt;
  return pipeline::merge_runs(std::move(*parts));
}

void MpiMonteCarloDriver::agree_or_throw(int exit_code, const std::exception_ptr& failure) const {
  const RankAgreement agreed = allreduce_agreement(exit_code);
  if (agreed.exit_code == 0) return;
  settled_ = true; // no collective follows: every rank leaves with the agreed code
  agreed_failure_ = agreed;
  if (failure) std::rethrow_exception(failure);
  throw OtherRankFailed(agreed.exit_code);
}

std::optional<pipeline::MonteCarloRun> MpiMonteCarloDriver::run(const workbench::Workbench& wb,
                                                                const compensation::CorrectionTable& nominal,
                                                                const pipeline::MonteCarloOptions& options) const {
  if (options.adaptive_tolerance_um <= 0.0) return MonteCarloDriver::run(wb, nominal, options);
  // This rank's block of every batch: the same offsets within each (shard_range of the batch).
  const auto [block_first, block_last] = pipeline::shard_range(options.adaptive_batch, rank_ + 1, size_);
  pipeline::MonteCarloOptions block_options = options;
  block_options.samples = options.adaptive_max_samples; // the batches' indices lie within the limit
  long long done_before = 0;
  if (options.on_sample_done) {
    const long long total = samples_on_this_process(options);
    block_options.on_sample_done = [&, total](long long done, long long) { options.on_sample_done(done_before + done, total); };
  }
  std::exception_ptr rank0_failure; // rank 0: merging a batch failed; told to the others with the stop
  auto run = pipeline::run_adaptive_batches(
      options,
      [&](long long first, long long last) -> std::optional<pipeline::MonteCarloRun> {
        PackedRun packed;
        std::exception_ptr failure;
        try {
          pipeline::MonteCarloRun local =
              pipeline::run_monte_carlo_samples(wb, nominal, block_options, first + block_first, first + block_last);
          local.samples_total = last; // the run so far, as the in-process loop counts it
          packed = pack(local);
        } catch (...) {
          failure = std::current_exception();
        }
        done_before += block_last - block_first;
        agree_or_throw(failure ? exit_code_of(failure) : 0, failure);
        auto parts = gather_parts(packed, rank_, size_, comm_);
        if (!parts) return std::nullopt;
        try {
          pipeline::MonteCarloRun batch = pipeline::merge_runs(std::move(*parts));
          bool whole = batch.samples.size() == static_cast<std::size_t>(last - first);
          for (std::size_t i = 0; whole && i < batch.samples.size(); ++i)
            whole = batch.samples[i].index == first + static_cast<long long>(i);
          if (!whole)
            throw std::invalid_argument(fmt::format("the MPI ranks sent other samples than {}..{} of the batch", first, last - 1));
          return batch;
        } catch (...) {
          rank0_failure = std::current_exception();
          return std::nullopt; // the loop then asks agree(), which tells the others
        }
      },
      [&](bool stop) {
        std::array<int, 2> decision{stop ? 1 : 0, rank0_failure ? exit_code_of(rank0_failure) : 0};
        MPI_Bcast(decision.data(), 2, MPI_INT, 0, comm_);
        if (decision[1] != 0) {
          settled_ = true;
          agreed_failure_ = RankAgreement{decision[1], 0};
          if (rank0_failure) std::rethrow_exception(rank0_failure);
          throw OtherRankFailed(decision[1]);
        }
        return decision[0] != 0;
      });
  settled_ = true; // past the last collective: rank 0 writes the files, its failure its own
  return run;
}

} // namespace geartopo::app
