#include "geartopo/pipeline/monte_carlo.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/core/atomic_file.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/core/input_file.hpp"
#include "geartopo/core/parallel.hpp"
#include "geartopo/core/text_field.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/grinding/machine_process.hpp"
#include "geartopo/grinding/topology_plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>

namespace geartopo::pipeline {
namespace {

// SplitMix64 (Steele, Lea, Flood 2014): a counter-based generator; one stream per (seed, sample).
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in (0, 1): 53 random bits, never 0 (the logarithm below).
  double uniform() { return (static_cast<double>(next() >> 11) + 0.5) * 0x1.0p-53; }
  /// Standard normal by Box–Muller (one value per call, the second is dropped: the stream stays simple to follow).
  double normal() {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
};

SplitMix64 sample_stream(std::uint64_t seed, long long k) {
  SplitMix64 mix{seed};
  const std::uint64_t a = mix.next();
  SplitMix64 per_sample{a ^ static_cast<std::uint64_t>(k) * 0xD1B54A32D192ED03ull};
  (void)per_sample.next(); // decorrelate neighbouring k
  return per_sample;
}

/// The probe's own stream of sample k (MonteCarloOptions::probe_noise_um): seeded by the second number of the seed's
/// SplitMix64 sequence (sample_stream takes the first), so the machine's draws of sample k are the same with or
/// without probe noise.
SplitMix64 probe_stream(std::uint64_t seed, long long k) {
  SplitMix64 mix{seed};
  (void)mix.next();
  const std::uint64_t b = mix.next();
  SplitMix64 per_sample{b ^ static_cast<std::uint64_t>(k) * 0xD1B54A32D192ED03ull};
  (void)per_sample.next();
  return per_sample;
}

std::string_view ascii_name(evaluation::Quantity q) {
  using evaluation::Quantity;
  switch (q) {
  case Quantity::SinglePitch: return "f_p";
  case Quantity::CumulativePitch: return "F_p";
  case Quantity::ProfileSlope: return "f_Halpha";
  case Quantity::ProfileForm: return "f_falpha";
  case Quantity::ProfileTotal: return "F_alpha";
  case Quantity::HelixSlope: return "f_Hbeta";
  case Quantity::HelixForm: return "f_fbeta";
  case Quantity::HelixTotal: return "F_beta";
  case Quantity::Runout: return "F_r";
  }
  return "?";
}


std::vector<machine::ErrorSource> full_map(const std::vector<machine::ErrorSource>& given) {
  std::vector<machine::ErrorSource> all;
  all.reserve(machine::kComponentCount);
  for (int k = 0; k < machine::kComponentCount; ++k) all.push_back(machine::ErrorSource::zero(machine::component_at(k)));
  for (const auto& s : given) all[static_cast<size_t>(machine::index(s.id()))] = s;
  return all;
}

/// Lower Cholesky factor of the scene's effect correlation (N × N), empty when the values are independent. A
/// correlation that is not positive definite (rounding of a nearly singular fit) gets a small ridge.
Eigen::MatrixXd correlation_factor(const scene::Scene& s) {
  if (s.effect_correlation.size() == 0) return {};
  Eigen::MatrixXd C = s.effect_correlation;
  for (double ridge = 0.0; ridge < 1.0; ridge = ridge == 0.0 ? 1e-12 : ridge * 10.0) {
    const Eigen::LLT<Eigen::MatrixXd> llt((C + ridge * Eigen::MatrixXd::Identity(C.rows(), C.cols())) / (1.0 + ridge));
    if (llt.info() == Eigen::Success) return llt.matrixL();
  }
  return Eigen::MatrixXd::Identity(C.rows(), C.cols());
}

/// One standard normal deviate per effect value that has an uncertainty slot (scene order), drawn in that order, then
/// correlated by the factor L (z ← L z) when there is one.
Eigen::VectorXd effect_deviates(const scene::Scene& s, const Eigen::MatrixXd& L, SplitMix64& rng) {
  std::vector<double> z;
  for (size_t e = 0; e < s.effects.size() && e < s.effect_uncertainties.size(); ++e) {
    const auto params = effects::make_effect(s.effects[e].type)->parameters();
    for (size_t v = 0; v < s.effect_uncertainties[e].size() && v < s.effects[e].values.size() && v < params.size(); ++v)
      z.push_back(rng.normal());
  }
  Eigen::VectorXd out = Eigen::Map<Eigen::VectorXd>(z.data(), static_cast<Eigen::Index>(z.size()));
  if (L.rows() == out.size() && L.rows() > 0) out = L * out;
  return out;
}

} // namespace

GearQuantities gear_quantities(const workbench::IsoResult& iso, const std::vector<grinding::FlankTopology>& topo) {
  GearQuantities g;
  const auto add = [&g](std::string name, double v) {
    g.names.push_back(std::move(name));
    g.values.push_back(v);
  };
  const auto& c = iso.evaluation.classification;
  for (const auto& q : c.quantities) {
    // |value|: the worst slope's sign flips with the flank that is worst, which would split one band in two; the
    // class is judged by |value| too (evaluation/gear_evaluation.hpp, QuantityClass).
    add(fmt::format("{}_um", ascii_name(q.quantity)), std::abs(q.worst_value_um));
    if (q.flank_class) add(fmt::format("{}_class", ascii_name(q.quantity)), *q.flank_class);
  }
  if (c.overall) add("overall_class", *c.overall);
  add("largest_abs_um", grinding::largest_abs_deviation_um(topo));
  std::map<int, std::pair<double, double>> mean_by_tooth; // tooth → (left, right) mean grid deviation
  std::map<int, int> sides;
  for (const auto& ft : topo) {
    if (ft.grid.empty()) continue;
    double sum = 0.0;
    for (const auto& p : ft.grid) sum += p.deviation_um;
    auto& m = mean_by_tooth[ft.tooth];
    (ft.flank == Flank::Left ? m.first : m.second) = sum / static_cast<double>(ft.grid.size());
    ++sides[ft.tooth];
  }
  double thickness = 0.0, rotation = 0.0;
  int teeth = 0;
  for (const auto& [tooth, m] : mean_by_tooth) {
    if (sides[tooth] != 2) continue;
    thickness += m.first + m.second;
    rotation += 0.5 * (m.first - m.second);
    ++teeth;
  }
  if (teeth > 0) {
    add("thickness_um", thickness / teeth);
    add("rotation_um", rotation / teeth);
  }
  return g;
}

std::map<int, machine::Vector5d> draw_stroke_offsets(const std::set<int>& spaces, const machine::Vector5d& repeatability_sd,
                                                     const std::function<double()>& standard_normal) {
  std::map<int, machine::Vector5d> offsets;
  for (const int s : spaces)
    for (int a = 0; a < 5; ++a) offsets[s](a) = repeatability_sd(a) * standard_normal();
  return offsets;
}

compensation::CorrectionTable with_stroke_offsets(const compensation::CorrectionTable& base,
                                                  const std::map<int, machine::Vector5d>& offsets) {
  std::vector<compensation::CorrectionRow> rows = base.rows();
  for (auto& r : rows) {
    const auto it = offsets.find(r.space);
    if (it == offsets.end()) throw std::invalid_argument(fmt::format("no stroke offset for space {}", r.space));
    r.correction += it->second;
  }
  return compensation::CorrectionTable(std::move(rows));
}

compensation::CorrectionTable rounded_to_resolution(const compensation::CorrectionTable& table,
                                                    const machine::Vector5d& resolution) {
  std::vector<compensation::CorrectionRow> rows = table.rows();
  for (auto& r : rows)
    for (int i = 0; i < 5; ++i)
      if (resolution(i) > 0.0) r.correction(i) = resolution(i) * std::round(r.correction(i) / resolution(i));
  return compensation::CorrectionTable(std::move(rows));
}

std::pair<long long, long long> shard_range(long long samples, int shard, int shards) {
  if (samples < 1) throw std::invalid_argument(fmt::format("samples {} < 1", samples));
  if (shards < 1 || shard < 1 || shard > shards || shards > samples)
    throw std::invalid_argument(fmt::format("shard {}/{}: need 1 ≤ shard ≤ shards ≤ samples ({})", shard, shards, samples));
  const auto at = [&](long long i) { return samples * i / shards; }; // exact in integers
  return {at(shard - 1), at(shard)};
}

MonteCarloRun run_monte_carlo_samples(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal,
                                      const MonteCarloOptions& options, long long first, long long last) {
  if (first < 0 || first > last || last > options.samples)
    throw std::invalid_argument(fmt::format("samples [{}, {}) are not within the run's {}", first, last, options.samples));
  if (!(options.probe_noise_um >= 0.0) || !std::isfinite(options.probe_noise_um))
    throw std::invalid_argument(fmt::format("probe noise {} µm: need a finite σ ≥ 0", options.probe_noise_um));
  const auto& unc = wb.scene.machine.uncertainty;
  const auto nominal_map = full_map(wb.scene.machine.sources);
  const compensation::CorrectionTable applied = rounded_to_resolution(nominal, unc.resolution);
  std::vector<compensation::CorrectionRow> zero_rows = nominal.rows();
  for (auto& r : zero_rows) r.correction.setZero();
  const compensation::CorrectionTable uncorrected(std::move(zero_rows));
  std::set<int> spaces;
  for (const auto& r : nominal.rows()) spaces.insert(r.space);
  const Eigen::MatrixXd effect_correlation_factor = correlation_factor(wb.scene);
  bool effects_uncertain = false;
  for (const auto& us : wb.scene.effect_uncertainties)
    for (double u : us) effects_uncertain = effects_uncertain || u > 0.0;

  grinding::SimulationOptions so;
  so.rows = wb.scene.grid.rows;
  so.cols = wb.scene.grid.cols;
  so.profile_points = wb.scene.grid.profile_points;
  so.helix_points = wb.scene.grid.helix_points;
  so.teeth = wb.scene.grid.teeth;
  so.threads = 1; // parallel over samples instead
  const auto& g = wb.setup.geometry();
  const grinding::TopologyPlan plan(wb.setup, so); // the points' geometry, computed once for every gear

  MonteCarloRun run;
  run.samples_total = options.samples;
  run.seed = options.seed;
  run.iso = options.iso;
  run.probe_noise_um = options.probe_noise_um;
  const auto count = static_cast<int>(last - first);
  std::vector<GearQuantities> before(static_cast<size_t>(count)), after(static_cast<size_t>(count));
  std::atomic<long long> done{0};
  std::atomic<bool> stopped{false}; // on_sample_done threw: start no more samples
  parallel_for(count, options.threads, [&](int i) {
    if (stopped) return;
    const long long k = first + i;
    SplitMix64 rng = sample_stream(options.seed, k);
    // Draws in a fixed order: 43 map offsets, then per space (increasing) 5 axes before, then 5 axes after.
    std::vector<machine::ErrorSource> truth;
    truth.reserve(nominal_map.size());
    // Each: + z·u, u the scene's constant, or z·u(p) from the component's table column (ErrorSource::drawn).
    for (size_t c = 0; c < nominal_map.size(); ++c) truth.push_back(nominal_map[c].drawn(rng.normal(), unc.component_u[c]));
    const std::function<double()> standard_normal = [&rng] { return rng.normal(); };
    const auto off_before = draw_stroke_offsets(spaces, unc.repeatability, standard_normal);
    const auto off_after = draw_stroke_offsets(spaces, unc.repeatability, standard_normal);

    // Effects with uncertain values (Scene::effect_uncertainties, e.g. identified by diagnosis): drawn last, each value within its standard
    // uncertainty and jointly with the scene's correlation of them (effect_correlation_factor), held inside the
    // effect's allowed range.
    std::vector<std::unique_ptr<effects::Effect>> drawn_effects;
    if (effects_uncertain) {
      std::vector<scene::EffectSpec> specs = wb.scene.effects;
      const Eigen::VectorXd z = effect_deviates(wb.scene, effect_correlation_factor, rng); // N, in scene order
      Eigen::Index at = 0;
      for (size_t e = 0; e < specs.size() && e < wb.scene.effect_uncertainties.size(); ++e) {
        auto& spec = specs[e];
        const auto& us = wb.scene.effect_uncertainties[e];
        const auto params = effects::make_effect(spec.type)->parameters();
        for (size_t v = 0; v < us.size() && v < spec.values.size() && v < params.size(); ++v)
          spec.values[v] = std::clamp(spec.values[v] + us[v] * z(at++), params[v].lo, params[v].hi);
      }
      drawn_effects = workbench::make_effects(specs, wb.setup);
    }
    const auto& sample_effects = effects_uncertain ? drawn_effects : wb.effects;

    const machine::MachineModel model(wb.machine.strokes(), std::move(truth));
    const grinding::MachineProcess machine_process(model, wb.scene.machine.datum_face_z_mm);
    std::unique_ptr<effects::EffectsProcess> with_effects;
    if (!sample_effects.empty()) with_effects = std::make_unique<effects::EffectsProcess>(machine_process, sample_effects);
    const grinding::GrindingProcess& true_machine =
        with_effects ? static_cast<const grinding::GrindingProcess&>(*with_effects) : machine_process;

    const auto table_before = with_stroke_offsets(uncorrected, off_before);
    const auto table_after = with_stroke_offsets(applied, off_after);
    const compensation::CompensatedProcess gear1(true_machine, table_before), gear2(true_machine, table_after);
    auto topo1 = plan.simulate(gear1, so.threads);
    auto topo2 = plan.simulate(gear2, so.threads);
    if (options.probe_noise_um > 0.0) { // both gears measured, gear 1 first, from the probe's own stream of (seed, k)
      SplitMix64 probe = probe_stream(options.seed, k);
      const std::function<double()> probe_normal = [&probe] { return probe.normal(); };
      diagnosis::add_probe_noise(topo1, options.probe_noise_um, probe_normal);
      diagnosis::add_probe_noise(topo2, options.probe_noise_um, probe_normal);
    }
    before[static_cast<size_t>(i)] = gear_quantities(workbench::evaluate_iso(g, wb.setup.ranges(), topo1, options.iso), topo1);
    after[static_cast<size_t>(i)] = gear_quantities(workbench::evaluate_iso(g, wb.setup.ranges(), topo2, options.iso), topo2);
    if (options.on_sample_done) {
      try {
        options.on_sample_done(++done, count);
      } catch (...) {
        stopped = true;
        throw; // parallel_for rethrows the first exception once its workers are done
      }
    }
  });

  // Names: those every gear has (a class can be refused on one gear and given on another only if the gear leaves
  // the range of validity, which a draw cannot change; the check is kept all the same).
  if (count > 0) run.names = before.front().names;
  for (int i = 0; i < count; ++i) {
    const auto& b = before[static_cast<size_t>(i)];
    const auto& a = after[static_cast<size_t>(i)];
    if (b.names != run.names || a.names != run.names)
      throw std::runtime_error(fmt::format("Monte Carlo sample {}: the evaluation gave other quantities than sample {}",
                                           first + i, first));
    run.samples.push_back({first + i, b.values, a.values});
  }
  return run;
}

std::optional<MonteCarloRun> run_adaptive_batches(
    const MonteCarloOptions& options, const std::function<std::optional<MonteCarloRun>(long long first, long long last)>& run_batch,
    const std::function<bool(bool stop)>& agree) {
  if (options.adaptive_batch < 2 || options.adaptive_max_samples < 2 * options.adaptive_batch)
    throw std::invalid_argument(fmt::format("adaptive Monte Carlo: batch {} and at most {} samples: need a batch ≥ 2 and "
                                            "room for two batches", options.adaptive_batch, options.adaptive_max_samples));
  std::optional<MonteCarloRun> run;
  for (long long h = 1;; ++h) {
    std::optional<MonteCarloRun> batch = run_batch((h - 1) * options.adaptive_batch, h * options.adaptive_batch);
    bool stop = false;
    if (batch) { // the deciding process
      if (!run) {
        run.emplace();
        run->names = batch->names, run->seed = batch->seed, run->iso = batch->iso, run->probe_noise_um = batch->probe_noise_um;
      }
      for (auto& smp : batch->samples) run->samples.push_back(std::move(smp));
      run->samples_total = h * options.adaptive_batch;
      stop = (h >= 2 && adaptive_stability(*run, options.adaptive_batch, options.adaptive_tolerance_um).stable) ||
             (h + 1) * options.adaptive_batch > options.adaptive_max_samples; // the limit: the last whole batch within it
    }
    if (agree(stop)) break;
  }
  return run;
}

namespace {

MonteCarloRun run_adaptive(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal,
                           const MonteCarloOptions& options) {
  if (options.shards != 1)
    throw std::invalid_argument("adaptive Monte Carlo runs in one process: its stop depends on all samples (no --shard)");
  // Progress counts over the batches towards the limit (the stop is not known before): batch h's samples continue the
  // count where batch h − 1 ended.
  MonteCarloOptions batch_options = options;
  batch_options.samples = options.adaptive_max_samples;
  long long done_before = 0;
  if (options.on_sample_done)
    batch_options.on_sample_done = [&](long long done, long long) {
      options.on_sample_done(done_before + done, options.adaptive_max_samples);
    };
  auto run = run_adaptive_batches(
      options,
      [&](long long first, long long last) -> std::optional<MonteCarloRun> {
        done_before = first;
        return run_monte_carlo_samples(wb, nominal, batch_options, first, last);
      },
      [](bool stop) { return stop; });
  return std::move(*run);
}

} // namespace

MonteCarloRun run_monte_carlo(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal,
                              const MonteCarloOptions& options) {
  if (options.adaptive_tolerance_um > 0.0) return run_adaptive(wb, nominal, options);
  const auto [first, last] = shard_range(options.samples, options.shard, options.shards);
  return run_monte_carlo_samples(wb, nominal, options, first, last);
}

AdaptiveStability adaptive_stability(const MonteCarloRun& run, long long batch, double tolerance_um) {
  const auto m = static_cast<long long>(run.samples.size());
  if (batch < 1 || m < batch || m % batch != 0)
    throw std::invalid_argument(fmt::format("{} samples are not whole batches of {}", m, batch));
  for (long long i = 0; i < m; ++i)
    if (run.samples[static_cast<size_t>(i)].index != i) throw std::invalid_argument(fmt::format("sample {} is missing", i));
  AdaptiveStability st;
  st.batches = m / batch;
  const auto h = static_cast<double>(st.batches);
  for (size_t n = 0; n < run.names.size(); ++n) {
    if (!run.names[n].ends_with("_um")) continue; // classes are whole numbers: their ends do not converge smoothly
    for (const bool after : {false, true}) {
      std::vector<Band> bands;
      for (long long r = 0; r < st.batches; ++r) {
        std::vector<double> v;
        for (long long i = r * batch; i < (r + 1) * batch; ++i) {
          const auto& smp = run.samples[static_cast<size_t>(i)];
          v.push_back(after ? smp.after[n] : smp.before[n]);
        }
        bands.push_back(coverage_band(std::move(v)));
      }
      for (const auto& [what, member] : {std::pair{"median", &Band::median}, {"low", &Band::low}, {"high", &Band::high}}) {
        double mean = 0.0;
        for (const auto& b : bands) mean += b.*member;
        mean /= h;
        double ss = 0.0;
        for (const auto& b : bands) ss += (b.*member - mean) * (b.*member - mean);
        const double two_s = st.batches < 2 ? std::numeric_limits<double>::infinity() : 2.0 * std::sqrt(ss / (h * (h - 1.0)));
        if (two_s > st.worst_two_s_um || st.worst.empty()) {
          st.worst_two_s_um = two_s;
          st.worst = fmt::format("{}.{} {}", after ? "after" : "before", run.names[n], what);
        }
      }
    }
  }
  st.stable = st.batches >= 2 && st.worst_two_s_um <= tolerance_um;
  return st;
}

MonteCarloRun merge_runs(std::vector<MonteCarloRun> parts) {
  if (parts.empty()) throw std::invalid_argument("no partial results to merge");
  MonteCarloRun out;
  out.samples_total = parts.front().samples_total;
  out.seed = parts.front().seed;
  out.iso = parts.front().iso;
  out.probe_noise_um = parts.front().probe_noise_um;
  out.names = parts.front().names;
  for (size_t p = 0; p < parts.size(); ++p) {
    const auto& part = parts[p];
    if (part.samples_total != out.samples_total || part.seed != out.seed)
      throw std::invalid_argument(fmt::format("part {}: {} samples, seed {} (part 1: {} samples, seed {}): not the same run",
                                              p + 1, part.samples_total, part.seed, out.samples_total, out.seed));
    if (part.iso.direction != out.iso.direction || part.iso.helix_slope_sign != out.iso.helix_slope_sign)
      throw std::invalid_argument(fmt::format("part {}: ISO options {}, {} (part 1: {}, {}): not the same run", p + 1,
                                              evaluation::to_string(part.iso.direction),
                                              evaluation::to_string(part.iso.helix_slope_sign),
                                              evaluation::to_string(out.iso.direction),
                                              evaluation::to_string(out.iso.helix_slope_sign)));
    if (part.probe_noise_um != out.probe_noise_um)
      throw std::invalid_argument(fmt::format("part {}: probe noise {} µm (part 1: {} µm): not the same run", p + 1,
                                              part.probe_noise_um, out.probe_noise_um));
    if (part.names != out.names)
      throw std::invalid_argument(fmt::format("part {}: other quantities than part 1 (another scene?)", p + 1));
    for (const auto& s : part.samples) out.samples.push_back(s);
  }
  std::sort(out.samples.begin(), out.samples.end(),
            [](const MonteCarloSample& a, const MonteCarloSample& b) { return a.index < b.index; });
  for (size_t i = 1; i < out.samples.size(); ++i)
    if (out.samples[i].index == out.samples[i - 1].index)
      throw std::invalid_argument(fmt::format("sample {} is in two parts", out.samples[i].index));
  return out;
}

Band coverage_band(std::vector<double> v, double coverage) {
  if (v.empty()) throw std::invalid_argument("coverage_band: no values");
  std::sort(v.begin(), v.end());
  const auto m = static_cast<long long>(v.size());
  const double pm = coverage * static_cast<double>(m);
  long long q = std::abs(pm - std::round(pm)) < 1e-9 ? std::llround(pm) : static_cast<long long>(std::floor(pm + 0.5));
  q = std::clamp(q, 0ll, m - 1);
  long long r = (m - q) % 2 == 0 ? (m - q) / 2 : (m - q + 1) / 2; // 1-based
  r = std::max(r, 1ll);
  const long long hi = std::min(r + q, m);
  Band b;
  b.low = v[static_cast<size_t>(r - 1)];
  b.high = v[static_cast<size_t>(hi - 1)];
  b.median = m % 2 == 1 ? v[static_cast<size_t>(m / 2)] : 0.5 * (v[static_cast<size_t>(m / 2 - 1)] + v[static_cast<size_t>(m / 2)]);
  return b;
}

int MonteCarloSummary::find(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

MonteCarloSummary summarise(const MonteCarloRun& run) {
  if (static_cast<long long>(run.samples.size()) != run.samples_total)
    throw std::invalid_argument(fmt::format("{} of {} samples: merge every shard first", run.samples.size(), run.samples_total));
  for (size_t i = 0; i < run.samples.size(); ++i)
    if (run.samples[i].index != static_cast<long long>(i))
      throw std::invalid_argument(fmt::format("sample {} is missing", i));
  MonteCarloSummary s;
  s.samples = run.samples_total;
  s.seed = run.seed;
  s.iso = run.iso;
  s.probe_noise_um = run.probe_noise_um;
  s.names = run.names;
  for (size_t n = 0; n < run.names.size(); ++n) {
    std::vector<double> b, a;
    for (const auto& smp : run.samples) b.push_back(smp.before[n]), a.push_back(smp.after[n]);
    s.before.push_back(coverage_band(std::move(b)));
    s.after.push_back(coverage_band(std::move(a)));
  }
  return s;
}

void write_run_csv(const std::filesystem::path& file, const MonteCarloRun& run) {
  output::write_atomically(file, [&](std::ostream& out) {
    out << "# geartopo Monte Carlo partial result (docs/monte-carlo.md); merge with: geartopo merge\n";
    out << "# samples_total: " << run.samples_total << "\n# seed: " << run.seed << "\n";
    out << "# iso_direction: " << evaluation::to_string(run.iso.direction)
        << "\n# helix_slope_sign: " << evaluation::to_string(run.iso.helix_slope_sign) << "\n";
    out << fmt::format("# probe_noise_um: {}\n", run.probe_noise_um);
    out << "sample";
    for (const auto& n : run.names) out << ",before." << n;
    for (const auto& n : run.names) out << ",after." << n;
    out << "\n";
    for (const auto& s : run.samples) {
      out << s.index;
      for (double v : s.before) out << fmt::format(",{}", v); // shortest form that reads back to the same double
      for (double v : s.after) out << fmt::format(",{}", v);
      out << "\n";
    }
  });
}

MonteCarloRun read_run_csv(const std::filesystem::path& file) {
  const std::string text = input::read_input_file(file, input::kMaxMeasurementBytes, "Monte Carlo partial result");
  const std::string name = file.string();
  MonteCarloRun run;
  bool have_total = false, have_seed = false, have_header = false;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  const auto fail = [&](int column, const std::string& field, const std::string& message) {
    throw InputError(SourcePosition{name, line_no, column}, field, message);
  };
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::string_view view(line);
    if (line_no == 1) text::strip_bom(view);
    if (view.empty()) continue;
    if (view.front() == '#') {
      const auto take = [&](std::string_view key, auto& value, bool& have) {
        if (view.substr(0, key.size()) != key) return;
        const auto rest = view.substr(key.size());
        if (text::parse_number(rest, value) != std::errc())
          fail(static_cast<int>(key.size()) + 1, std::string(key.substr(2, key.size() - 4)),
               fmt::format("'{}' is not a whole number", text::excerpt(rest)));
        have = true;
      };
      take("# samples_total: ", run.samples_total, have_total);
      take("# seed: ", run.seed, have_seed);
      if (constexpr std::string_view key = "# probe_noise_um: "; view.substr(0, key.size()) == key) {
        const auto rest = view.substr(key.size());
        if (text::parse_number(rest, run.probe_noise_um) != std::errc() || !std::isfinite(run.probe_noise_um) ||
            run.probe_noise_um < 0.0)
          fail(static_cast<int>(key.size()) + 1, "probe_noise_um", fmt::format("'{}' is not a σ ≥ 0 (µm)", text::excerpt(rest)));
      }
      // Words: absent in files written before they were recorded (compensate then always used the defaults).
      const auto word = [&](std::string_view key, auto parse, auto& value) {
        if (view.substr(0, key.size()) != key) return;
        const auto parsed = parse(view.substr(key.size()));
        if (!parsed) fail(static_cast<int>(key.size()) + 1, std::string(key.substr(2, key.size() - 4)),
                          fmt::format("'{}' is not one of the words geartopo writes", text::excerpt(view.substr(key.size()))));
        value = *parsed;
      };
      word("# iso_direction: ", evaluation::parse_iso_direction, run.iso.direction);
      word("# helix_slope_sign: ", evaluation::parse_helix_slope_sign, run.iso.helix_slope_sign);
      continue;
    }
    std::vector<std::string_view> fields;
    for (size_t start = 0;;) {
      const auto comma = view.find(',', start);
      fields.push_back(view.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (!have_header) {
      if (!have_total || !have_seed) fail(1, "header", "'# samples_total: M' and '# seed: S' must come before the header");
      if (run.samples_total < 1) fail(1, "samples_total", "must be ≥ 1");
      if (fields.empty() || fields[0] != "sample" || fields.size() % 2 != 1)
        fail(1, "header", "expected sample,before.<name>,…,after.<name>,…");
      const size_t n = (fields.size() - 1) / 2;
      for (size_t i = 0; i < n; ++i) {
        const auto b = fields[1 + i], a = fields[1 + n + i];
        if (b.substr(0, 7) != "before." || a.substr(0, 6) != "after." || b.substr(7) != a.substr(6))
          fail(static_cast<int>(2 + i), "header", "expected before.<name> … after.<name> in the same order");
        run.names.emplace_back(b.substr(7));
      }
      have_header = true;
      continue;
    }
    if (fields.size() != 1 + 2 * run.names.size())
      fail(1, "sample", fmt::format("{} fields, the header has {}", fields.size(), 1 + 2 * run.names.size()));
    MonteCarloSample s;
    if (text::parse_number(fields[0], s.index) != std::errc() || s.index < 0 || s.index >= run.samples_total)
      fail(1, "sample", fmt::format("'{}' is not a sample number of 0..{}", text::excerpt(fields[0]), run.samples_total - 1));
    for (size_t i = 1; i < fields.size(); ++i) {
      double v = 0.0;
      if (text::parse_number(fields[i], v) != std::errc() || !std::isfinite(v))
        fail(static_cast<int>(i + 1), i <= run.names.size() ? "before." + run.names[i - 1] : "after." + run.names[i - 1 - run.names.size()],
             fmt::format("'{}' is not a finite number", text::excerpt(fields[i])));
      (i <= run.names.size() ? s.before : s.after).push_back(v);
    }
    if (!run.samples.empty() && s.index <= run.samples.back().index)
      fail(1, "sample", "sample numbers must increase");
    run.samples.push_back(std::move(s));
  }
  if (!have_header) fail(0, "header", "no header line (sample,before.…): not a partial result");
  return run;
}

} // namespace geartopo::pipeline
