// geartopo-mpi — the MPI driver of compensate's Monte Carlo: shards per rank, one agreement, the gather on rank 0
// (mpi_driver.hpp). Units: none of its own (the samples are the library's µm and class quantities, moved as doubles).
#include "app/mpi_driver.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <sched.h>

#include <array>
#include <climits>
#include <cstdint>
#include <string>
#include <vector>

namespace geartopo::app {
namespace {

/// What a rank sends ahead of its samples: the lengths of its two buffers and the run's identity (merge_runs
/// compares seed, sample count and names, so a rank that computed something else is refused, not mixed in).
enum RankHeaderField { kRankNamesChars, kRankSampleDoubles, kRankSamplesTotal, kRankSeed, kRankHeaderFields };

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

/// Rank r's part as a run: names split at '\n', rows of (index, before…, after…).
pipeline::MonteCarloRun rank_part_as_run(int rank, const std::array<unsigned long long, kRankHeaderFields>& header, const char* names,
                                const double* values) {
  pipeline::MonteCarloRun part;
  part.samples_total = static_cast<long long>(header[kRankSamplesTotal]);
  part.seed = header[kRankSeed];
  const std::string joined(names, header[kRankNamesChars]);
  for (std::size_t start = 0; start < joined.size();) {
    const std::size_t end = std::min(joined.find('\n', start), joined.size());
    part.names.push_back(joined.substr(start, end - start));
    start = end + 1;
  }
  const std::size_t width = 1 + 2 * part.names.size(), count = header[kRankSampleDoubles];
  if (count % width != 0)
    throw std::invalid_argument(fmt::format("MPI rank {} sent {} values, not whole samples of {} quantities", rank, count,
                                            part.names.size()));
  for (std::size_t row = 0; row < count / width; ++row) {
    const double* v = values + row * width;
    pipeline::MonteCarloSample s;
    s.index = static_cast<long long>(v[0]);
    s.before.assign(v + 1, v + 1 + part.names.size());
    s.after.assign(v + 1 + part.names.size(), v + width);
    part.samples.push_back(std::move(s));
  }
  return part;
}

} // namespace

OtherRankFailed::OtherRankFailed(int code) : std::runtime_error("another MPI rank failed"), exit_code(code) {}

MpiMonteCarloDriver::MpiMonteCarloDriver(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

void MpiMonteCarloDriver::check(const pipeline::MonteCarloOptions& options) const {
  if (options.shards != 1)
    throw CLI::ValidationError("--shard", "geartopo-mpi gives rank r of n the shard r+1/n: leave --shard out");
  if (options.samples <= 0) return; // no prediction: nothing to scatter
  if (options.adaptive_tolerance_um > 0.0)
    throw CLI::ValidationError("--adaptive-tolerance-um",
                               "an adaptive run decides after every batch on all samples so far: not under MPI; run it "
                               "with geartopo compensate, or give geartopo-mpi a fixed --samples N");
  if (options.samples < size_)
    throw CLI::ValidationError("--samples", fmt::format("{} MPI ranks for {} samples: every rank needs a sample", size_,
                                                        options.samples));
}

pipeline::MonteCarloOptions MpiMonteCarloDriver::this_process(const pipeline::MonteCarloOptions& options) const {
  pipeline::MonteCarloOptions o = options;
  o.shard = rank_ + 1;
  o.shards = size_;
  if (o.threads <= 0) o.threads = cpus_bound_to_this_rank();
  return o;
}

std::string MpiMonteCarloDriver::split_hint() const { return "more MPI ranks (mpirun -n) on more machines"; }

RankAgreement MpiMonteCarloDriver::settle(int exit_code) const {
  if (settled_) throw std::logic_error("MpiMonteCarloDriver::settle called twice on one rank");
  settled_ = true;
  // {largest exit code, size − lowest failing rank}: one MPI_MAX reduction gives both.
  const std::array<int, 2> mine{exit_code, exit_code != 0 ? size_ - rank_ : 0};
  std::array<int, 2> all{};
  MPI_Allreduce(mine.data(), all.data(), 2, MPI_INT, MPI_MAX, comm_);
  return {all[0], all[1] > 0 ? size_ - all[1] : -1};
}

std::optional<pipeline::MonteCarloRun> MpiMonteCarloDriver::complete(pipeline::MonteCarloRun local) const {
  // Everything that can fail on this rank alone happens before settle(): after it, only collectives.
  std::string names;
  for (const auto& n : local.names) names += (names.empty() ? "" : "\n") + n;
  std::vector<double> values;
  values.reserve(local.samples.size() * (1 + 2 * local.names.size()));
  for (const auto& s : local.samples) {
    values.push_back(static_cast<double>(s.index)); // exact: indices < 2⁵³ (--samples ≤ 10⁶)
    values.insert(values.end(), s.before.begin(), s.before.end());
    values.insert(values.end(), s.after.begin(), s.after.end());
  }
  const int names_count = mpi_count_or_throw(names.size(), "the names");
  const int values_count = mpi_count_or_throw(values.size(), "the values");

  if (const RankAgreement agreed = settle(0); agreed.exit_code != 0) throw OtherRankFailed(agreed.exit_code);

  const std::array<unsigned long long, kRankHeaderFields> header{static_cast<unsigned long long>(names_count),
                                                             static_cast<unsigned long long>(values_count),
                                                             static_cast<unsigned long long>(local.samples_total),
                                                             local.seed};
  std::vector<std::array<unsigned long long, kRankHeaderFields>> headers(rank_ == 0 ? static_cast<std::size_t>(size_) : 0);
  MPI_Gather(header.data(), kRankHeaderFields, MPI_UNSIGNED_LONG_LONG, headers.data(), kRankHeaderFields, MPI_UNSIGNED_LONG_LONG,
             0, comm_);
  // Counts and displacements of the two gathers (rank 0 only). The totals fit an int: --samples ≤ 10⁶ (CLI range),
  // each 1 + 2 × (quantities: 22 on the default scene) doubles, 4.5·10⁷ of 2.1·10⁹.
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
  MPI_Gatherv(names.data(), names_count, MPI_CHAR, all_names.data(), names_counts.data(), names_displs.data(), MPI_CHAR,
              0, comm_);
  MPI_Gatherv(values.data(), values_count, MPI_DOUBLE, all_values.data(), values_counts.data(), values_displs.data(),
              MPI_DOUBLE, 0, comm_);
  if (rank_ != 0) return std::nullopt;

  std::vector<pipeline::MonteCarloRun> parts;
  for (int r = 0; r < size_; ++r) {
    const auto i = static_cast<std::size_t>(r);
    parts.push_back(rank_part_as_run(r, headers[i], all_names.data() + names_displs[i], all_values.data() + values_displs[i]));
  }
  return pipeline::merge_runs(std::move(parts));
}

} // namespace geartopo::app
