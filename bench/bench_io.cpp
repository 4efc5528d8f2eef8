// Reading speed of the measurement files, which can have millions of rows (docs/point-clouds.md):
//   ReadPointCloud — surfaces::read_point_cloud on a 10⁶-row x_mm,y_mm,z_mm file (30 MB, written once to /tmp);
//   ReadTopology   — grinding::read_topology_csv on the default gear's dense 50×100 topology (350 000 rows).
// Counter `rows`: rows parsed per second. Memory per row is checked by tests/robustness/test_streaming.cpp.
#include "bench_scene.hpp"

#include "geartopo/grinding/topology.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/surfaces/point_cloud.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <unistd.h>

using namespace geartopo;

namespace {

// A temporary file removed when the benchmark binary exits.
struct TempFile {
  explicit TempFile(const std::string& name)
      : path(std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_geartopo_bench_" + name)) {}
  ~TempFile() { std::filesystem::remove(path); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  std::filesystem::path path;
};

constexpr int kCloudRows = 1'000'000;

// Points on a helix-like path, all distinct (as tests/robustness/test_streaming.cpp writes them).
const TempFile& cloud_file() {
  static const TempFile f("cloud.csv");
  static const bool written = [] {
    std::FILE* out = std::fopen(f.path.c_str(), "w");
    std::fputs("x_mm,y_mm,z_mm\n", out);
    for (int i = 0; i < kCloudRows; ++i) {
      const double a = 1e-3 * i;
      std::fprintf(out, "%.6f,%.6f,%.6f\n", 290.0 * std::cos(a), 290.0 * std::sin(a), 1e-4 * i);
    }
    return std::fclose(out) == 0;
  }();
  if (!written) throw std::runtime_error(f.path.string() + ": cannot write");
  return f;
}

void BM_ReadPointCloud(benchmark::State& state) {
  const auto& file = cloud_file();
  for (auto _ : state) benchmark::DoNotOptimize(surfaces::read_point_cloud(file.path).data());
  state.counters["rows"] =
      benchmark::Counter(double(kCloudRows) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ReadPointCloud)->Name("ReadPointCloud/1e6rows")->Unit(benchmark::kMillisecond);

struct TopologyFile {
  TempFile file{"dense.csv"};
  size_t rows = 0;
};

const TopologyFile& dense_topology_file() {
  static TopologyFile f;
  static const bool written = [] {
    const auto& b = bench::default_scene();
    grinding::SimulationOptions o;
    o.method = grinding::Method::Linear; // only the file's size and format matter here
    o.dense_rows = 50;
    o.dense_cols = 100;
    const auto topo = grinding::simulate_topology(b.setup, b.process(), o);
    grinding::write_topology_csv(f.file.path, topo, grinding::GridKind::Dense);
    f.rows = grinding::topology_rows(topo, grinding::GridKind::Dense).size();
    return true;
  }();
  (void)written;
  return f;
}

void BM_ReadTopology(benchmark::State& state) {
  const auto& f = dense_topology_file();
  const int teeth = bench::default_scene().setup.geometry().teeth();
  for (auto _ : state) benchmark::DoNotOptimize(grinding::read_topology_csv(f.file.path, teeth).data());
  state.counters["rows"] = benchmark::Counter(double(f.rows) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ReadTopology)->Name("ReadTopology/dense50x100")->Unit(benchmark::kMillisecond);

} // namespace
