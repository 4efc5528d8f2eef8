#include "geartopo/pipeline/monte_carlo.hpp"

#include "geartopo/compensation/compensator.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/files/input_file.hpp"
#include "geartopo/core/parallel.hpp"
#include "geartopo/core/units.hpp"
#include "geartopo/pipeline/topology_sensitivities.hpp"

#include "sample_model.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <numbers>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>

namespace geartopo::pipeline {

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
  return compensation::CorrectionTable(std::move(rows), base.axes());
}

namespace {

/// Rounding error of a setpoint u (in resolution units): round(u) − u, periodic with mean 0 over a unit.
double rounding_error(double u) { return std::round(u) - u; }

/// ∫₀ᵘ rounding_error = −s²/2, s = u − round(u): every whole unit adds nothing (mean 0), so the integral is periodic.
double rounding_error_integral(double u) {
  const double s = u - std::round(u);
  return -0.5 * s * s;
}

/// Mean of the rounding error while the setpoint runs linearly from u to u + du (units).
double mean_rounding_error(double u, double du) {
  if (std::abs(du) < 1e-9) return rounding_error(u);
  return (rounding_error_integral(u + du) - rounding_error_integral(u)) / du;
}

/// The nominal command's change from row a to row b of axis `axis` (mm or rad; rotary axes by the shorter way round).
double command_change(const compensation::CorrectionRow& a, const compensation::CorrectionRow& b, int axis) {
  const double d = b.machine_axes.vector()(axis) - a.machine_axes.vector()(axis);
  if (axis < 3) return d;
  return std::remainder(d, 2.0 * std::numbers::pi);
}

} // namespace

compensation::CorrectionTable rounded_to_resolution(const compensation::CorrectionTable& table,
                                                    const machine::Vector5d& resolution) {
  const std::vector<compensation::CorrectionRow>& in = table.rows(); // by space, then stroke position
  std::vector<compensation::CorrectionRow> rows = in;
  for (size_t i = 0; i < in.size(); ++i) {
    const auto& r = in[i];
    // The row stands for the stroke from the midpoint to its previous row to the midpoint to its next (same space).
    const compensation::CorrectionRow* prev = i > 0 && in[i - 1].space == r.space ? &in[i - 1] : nullptr;
    const compensation::CorrectionRow* next = i + 1 < in.size() && in[i + 1].space == r.space ? &in[i + 1] : nullptr;
    const double l_prev = prev ? 0.5 * (r.z_stroke_mm - prev->z_stroke_mm) : 0.0;
    const double l_next = next ? 0.5 * (next->z_stroke_mm - r.z_stroke_mm) : 0.0;
    for (int a = 0; a < 5; ++a) {
      const double q = resolution(a);
      if (!(q > 0.0)) continue;
      // The controller rounds the setpoint, command + correction. Over the row's stretch the command moves (linearly
      // to the midpoints) while the correction is the row's: the setpoint's rounding error averaged over it. An axis
      // standing still (X, Y, A of a plain gear) keeps its whole error, round(δq) − δq; one that sweeps n units
      // (C: ≈ 1 165 units per mm of Z on the default gear; Z: 10⁴) averages to at most 1/(8n) of a unit.
      const double u = r.correction(a) / q;
      double mean = rounding_error(u);
      if (l_prev + l_next > 0.0) {
        const double du_prev = prev ? 0.5 * command_change(r, *prev, a) / q : 0.0;
        const double du_next = next ? 0.5 * command_change(r, *next, a) / q : 0.0;
        mean = (l_prev * mean_rounding_error(u, du_prev) + l_next * mean_rounding_error(u, du_next)) / (l_prev + l_next);
      }
      rows[i].correction(a) = r.correction(a) + q * mean;
    }
  }
  return compensation::CorrectionTable(std::move(rows), table.axes());
}

std::pair<long long, long long> shard_range(long long samples, int shard, int shards) {
  limits::require(limits::samples_refusal(samples, 1), "Monte Carlo samples");
  if (shards < 1 || shard < 1 || shard > shards || shards > samples)
    throw std::invalid_argument(fmt::format("shard {}/{}: need 1 ≤ shard ≤ shards ≤ samples ({})", shard, shards, samples));
  const auto at = [&](long long i) { return samples * i / shards; }; // exact in integers
  return {at(shard - 1), at(shard)};
}

namespace {

bool is_um(const std::string& name) { return name.ends_with("_um"); }

/// A run's preparation: the sample model and, for Sampling::Checked, the verdict of the exact samples on first order.
struct Prepared {
  std::unique_ptr<detail::SampleModel> model;
  SamplingReport report;
  bool linear = false;
};

Prepared prepare(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal, const MonteCarloOptions& options) {
  Prepared p;
  p.model = std::make_unique<detail::SampleModel>(wb, nominal, options, options.sampling != Sampling::Exact);
  const auto& g = wb.setup.geometry();
  switch (options.sampling) {
  case Sampling::Exact: p.report = {"exact", "forced", 0, 0.0, 0.0}; break;
  case Sampling::Linear: p.report = {"linear", "unchecked", 0, 0.0, 0.0}; p.linear = true; break;
  case Sampling::Checked: {
    // Samples 0 … kCheckSamples − 1 of the seed, exact and linear: the same decision in every shard, rank and batch.
    std::vector<double> point_diff(kCheckSamples, 0.0), quantity_diff(kCheckSamples, 0.0);
    parallel_for(kCheckSamples, options.threads, [&](int k) {
      const auto d = p.model->draw(k);
      const auto ex = p.model->exact(d);
      const auto li = p.model->linear(d, false);
      auto topo = p.model->layout();
      double pd = 0.0, qd = 0.0;
      for (const auto& [e, l] : {std::pair{&ex.before, &li.before}, {&ex.after, &li.after}}) {
        pd = std::max(pd, (flatten_deviations(*e) - *l).cwiseAbs().maxCoeff());
        set_deviations(topo, *l);
        const auto qe = gear_quantities(workbench::evaluate_iso(g, wb.setup.ranges(), *e, options.iso), *e);
        const auto ql = gear_quantities(workbench::evaluate_iso(g, wb.setup.ranges(), topo, options.iso), topo);
        if (qe.names != ql.names) {
          qd = std::numeric_limits<double>::infinity(); // a class refused on one and given on the other
          continue;
        }
        for (size_t n = 0; n < qe.names.size(); ++n)
          if (is_um(qe.names[n])) qd = std::max(qd, std::abs(qe.values[n] - ql.values[n]));
      }
      point_diff[static_cast<size_t>(k)] = pd;
      quantity_diff[static_cast<size_t>(k)] = qd;
    });
    p.report.checked_samples = kCheckSamples;
    p.report.largest_point_difference_um = *std::max_element(point_diff.begin(), point_diff.end());
    p.report.largest_quantity_difference_um = *std::max_element(quantity_diff.begin(), quantity_diff.end());
    p.linear = p.report.largest_quantity_difference_um <= kLinearAgreementUm; // false for ∞: the classes differed
    p.report.method = p.linear ? "linear" : "exact";
    p.report.reason = p.linear ? "checked" : "check failed";
    break;
  }
  }
  return p;
}

MonteCarloRun run_prepared(const Prepared& p, const workbench::Workbench& wb, const MonteCarloOptions& options,
                           long long first, long long last) {
  if (first < 0 || first > last || last > options.samples)
    throw std::invalid_argument(fmt::format("samples [{}, {}) are not within the run's {}", first, last, options.samples));
  const auto& g = wb.setup.geometry();
  MonteCarloRun run;
  run.samples_total = options.samples;
  run.seed = options.seed;
  run.iso = options.iso;
  run.probe_noise_um = options.probe_noise_um;
  run.gear = gear_record(g.spec());
  run.sampling = p.report;
  if (p.linear) run.without = p.model->without();
  const auto count = static_cast<int>(last - first);
  const size_t variants = run.without.size();
  std::vector<GearQuantities> before(static_cast<size_t>(count)), after(static_cast<size_t>(count));
  std::vector<std::vector<GearQuantities>> without(static_cast<size_t>(count));
  // Reports in order: the count is raised and reported under one lock, so a progress display (or a Python callback,
  // which takes its own lock) never sees 6 before 5.
  std::mutex report;
  long long done = 0;
  std::atomic<bool> stopped{false}; // on_sample_done threw: start no more samples
  if (options.on_prepared) options.on_prepared();
  parallel_for(count, options.threads, [&](int i) {
    if (stopped) return;
    const long long k = first + i;
    const auto d = p.model->draw(k);
    const auto quantities = [&](const std::vector<grinding::FlankTopology>& topo) {
      return gear_quantities(workbench::evaluate_iso(g, wb.setup.ranges(), topo, options.iso), topo);
    };
    if (p.linear) { // one topology per sample, its deviations replaced for each gear
      auto gears = p.model->linear(d, true);
      p.model->add_probe_noise(gears, k);
      auto topo = p.model->layout();
      const auto of = [&](const Eigen::VectorXd& v) {
        set_deviations(topo, v);
        return quantities(topo);
      };
      before[static_cast<size_t>(i)] = of(gears.before);
      after[static_cast<size_t>(i)] = of(gears.after);
      for (const auto& v : gears.after_without) without[static_cast<size_t>(i)].push_back(of(v));
    } else {
      auto gears = p.model->exact(d);
      p.model->add_probe_noise(gears, k);
      before[static_cast<size_t>(i)] = quantities(gears.before);
      after[static_cast<size_t>(i)] = quantities(gears.after);
    }
    if (options.on_sample_done) {
      try {
        const std::lock_guard lock(report);
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
    bool same = b.names == run.names && a.names == run.names && without[static_cast<size_t>(i)].size() == variants;
    MonteCarloSample smp{first + i, b.values, a.values, {}};
    for (const auto& w : without[static_cast<size_t>(i)]) {
      same = same && w.names == run.names;
      smp.after_without.push_back(w.values);
    }
    if (!same)
      throw std::runtime_error(fmt::format("Monte Carlo sample {}: the evaluation gave other quantities than sample {}",
                                           first + i, first));
    run.samples.push_back(std::move(smp));
  }
  return run;
}

} // namespace

MonteCarloRun run_monte_carlo_samples(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal,
                                      const MonteCarloOptions& options, long long first, long long last) {
  limits::require(limits::samples_refusal(options.samples, 1), "run_monte_carlo: samples");
  limits::require(limits::synthetic_noise_um_refusal(options.probe_noise_um), "run_monte_carlo: probe_noise_um");
  if (first < 0 || first > last || last > options.samples)
    throw std::invalid_argument(fmt::format("samples [{}, {}) are not within the run's {}", first, last, options.samples));
  return run_prepared(prepare(wb, nominal, options), wb, options, first, last);
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
        run->sampling = batch->sampling, run->without = batch->without;
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
  const Prepared prepared = prepare(wb, nominal, batch_options); // once for all batches
  auto run = run_adaptive_batches(
      options,
      [&](long long first, long long last) -> std::optional<MonteCarloRun> {
        done_before = first;
        MonteCarloOptions this_batch = batch_options;
        if (first > 0) this_batch.on_prepared = nullptr; // the estimate times the first batch from its start
        return run_prepared(prepared, wb, this_batch, first, last);
      },
      [](bool stop) { return stop; });
  return std::move(*run);
}

} // namespace

MonteCarloRun run_monte_carlo(const workbench::Workbench& wb, const compensation::CorrectionTable& nominal,
                              const MonteCarloOptions& options) {
  limits::require(limits::synthetic_noise_um_refusal(options.probe_noise_um), "run_monte_carlo: probe_noise_um");
  if (!(std::isfinite(options.adaptive_tolerance_um) && options.adaptive_tolerance_um >= 0.0))
    throw std::invalid_argument(fmt::format("run_monte_carlo: adaptive_tolerance_um: {} is not 0 (off) or a finite "
                                            "tolerance > 0 µm", options.adaptive_tolerance_um));
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

namespace {

/// One setting of a run as its partial result writes it: the key (write_run_csv's "# key: "), the value as written,
/// and why a part with another value is refused.
struct RunSetting {
  std::string key, value, why;
};

/// A run's settings in the order write_run_csv writes them, then the header's quantities.
std::vector<RunSetting> run_settings(const MonteCarloRun& r) {
  const auto or_none = [](const std::string& v) { return v.empty() ? std::string("not recorded") : v; };
  const std::string run = "not the same run";
  std::string quantities = fmt::format("{}", fmt::join(r.names, ","));
  for (const auto& w : r.without) quantities += ",without_" + w;
  return {{"samples_total", std::to_string(r.samples_total), run},
          {"seed", std::to_string(r.seed), run},
          {"iso_direction", std::string(evaluation::to_string(r.iso.direction)), run},
          {"helix_slope_sign", std::string(evaluation::to_string(r.iso.helix_slope_sign)), run},
          {"probe_noise_um", fmt::format("{} µm", r.probe_noise_um), run},
          {"sampling", r.sampling.method, run},
          {"sampling_reason", or_none(r.sampling.reason), run},
          {"linear_check_samples", std::to_string(r.sampling.checked_samples), run},
          {"linear_check_points_um", fmt::format("{} µm", r.sampling.largest_point_difference_um), run},
          {"linear_check_quantities_um", fmt::format("{} µm", r.sampling.largest_quantity_difference_um), run},
          {"scene_fingerprint", or_none(r.scene_fingerprint), "computed from another scene, error table or compensation setting"},
          {"gear", or_none(r.gear), "not the same gear"},
          {"header", quantities, "other quantities (another scene?)"}};
}

/// Where a part's setting stands: "b.csv:4" (a missing setting: at the part's header, before which it would stand),
/// or "part 2" for a run computed in memory; the line (0 when not known).
std::pair<std::string, int> setting_place(const MonteCarloRun& r, const std::string& key, const std::string& part) {
  if (r.source.empty()) return {part, 0};
  const auto at = r.lines.find(key);
  const auto header = r.lines.find("header");
  const int line = at != r.lines.end() ? at->second : header != r.lines.end() ? header->second : 0;
  return {line > 0 ? fmt::format("{}:{}", r.source, line) : r.source, line};
}

/// Refuses `part` (named `here`) unless its settings are those of `first` (named `first_name`): the first differing
/// setting in the part's file, as file:line: field, beside the first part's.
void require_same_run(const MonteCarloRun& part, const std::string& here, const MonteCarloRun& first,
                      const std::string& first_name) {
  const auto mine = run_settings(part), theirs = run_settings(first);
  std::optional<std::size_t> worst;
  int worst_line = 0;
  for (std::size_t k = 0; k < mine.size(); ++k) {
    if (mine[k].value == theirs[k].value) continue;
    const int line = setting_place(part, mine[k].key, here).second;
    if (!worst || (line > 0 && (worst_line == 0 || line < worst_line))) worst = k, worst_line = line;
  }
  if (!worst) return;
  const auto& differs = mine[*worst];
  const std::string theirs_at = setting_place(first, differs.key, first_name).first;
  const bool unrecorded = differs.key == "scene_fingerprint" && (part.scene_fingerprint.empty() || first.scene_fingerprint.empty());
  const std::string message =
      fmt::format("{} ({}: {}): {}", differs.value, theirs_at, theirs[*worst].value,
                  unrecorded ? "one was written before geartopo recorded it, so they cannot be shown to be of the same "
                               "scene: compute every shard with this geartopo"
                             : differs.why);
  if (part.source.empty()) throw std::invalid_argument(fmt::format("{}: {}: {}", here, differs.key, message));
  throw InputError(SourcePosition{part.source, worst_line, 0}, differs.key, message);
}

} // namespace

MonteCarloRun merge_runs(std::vector<MonteCarloRun> parts) {
  if (parts.empty()) throw std::invalid_argument("no partial results to merge");
  // "part 2 (b.csv)" when read from a file: the user must know which file to look at.
  const auto part_name = [&](size_t p) {
    return parts[p].source.empty() ? fmt::format("part {}", p + 1) : fmt::format("part {} ({})", p + 1, parts[p].source);
  };
  MonteCarloRun out;
  out.samples_total = parts.front().samples_total;
  out.seed = parts.front().seed;
  out.iso = parts.front().iso;
  out.probe_noise_um = parts.front().probe_noise_um;
  out.names = parts.front().names;
  out.sampling = parts.front().sampling;
  out.without = parts.front().without;
  out.scene_fingerprint = parts.front().scene_fingerprint;
  out.gear = parts.front().gear;
  std::vector<std::pair<long long, size_t>> from; // sample index → part it came from
  for (size_t p = 0; p < parts.size(); ++p) {
    const auto& part = parts[p];
    // A part of another run is refused at its first differing setting (file:line: field), beside the first part's.
    require_same_run(part, fmt::format("part {}", p + 1), parts.front(), "part 1");
    for (const auto& s : part.samples) {
      out.samples.push_back(s);
      from.emplace_back(s.index, p);
    }
  }
  std::sort(from.begin(), from.end());
  for (size_t i = 1; i < from.size(); ++i)
    if (from[i].first == from[i - 1].first)
      throw std::invalid_argument(fmt::format("sample {} is in two parts: {} and {}", from[i].first,
                                              part_name(std::min(from[i].second, from[i - 1].second)),
                                              part_name(std::max(from[i].second, from[i - 1].second))));
  std::sort(out.samples.begin(), out.samples.end(),
            [](const MonteCarloSample& a, const MonteCarloSample& b) { return a.index < b.index; });
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
  s.gear = run.gear;
  s.names = run.names;
  s.sampling = run.sampling;
  s.without = run.without;
  s.after_without.resize(run.without.size());
  for (size_t n = 0; n < run.names.size(); ++n) {
    std::vector<double> b, a;
    for (const auto& smp : run.samples) b.push_back(smp.before[n]), a.push_back(smp.after[n]);
    s.before.push_back(coverage_band(std::move(b)));
    s.after.push_back(coverage_band(std::move(a)));
    for (size_t w = 0; w < run.without.size(); ++w) {
      std::vector<double> v;
      for (const auto& smp : run.samples) v.push_back(smp.after_without[w][n]);
      s.after_without[w].push_back(coverage_band(std::move(v)));
    }
  }
  return s;
}

AfterLimit after_limit(const MonteCarloSummary& s) {
  AfterLimit out;
  const int overall = s.find("overall_class");
  if (overall < 0 || s.without.empty()) return out;
  out.measured = true;
  out.overall_class = s.after[static_cast<size_t>(overall)].median;
  // The limiting quantity: the ISO value with the largest median class after (the first in the evaluation's order
  // among equals).
  double worst_class = -1.0;
  for (size_t n = 0; n < s.names.size(); ++n) {
    const auto& name = s.names[n];
    if (!name.ends_with("_class") || name == "overall_class") continue;
    const std::string value_name = name.substr(0, name.size() - std::string_view("_class").size()) + "_um";
    if (s.find(value_name) < 0 || s.after[n].median <= worst_class) continue;
    worst_class = s.after[n].median;
    out.limiting_quantity = value_name;
  }
  const int limiting = out.limiting_quantity.empty() ? -1 : s.find(out.limiting_quantity);
  if (limiting >= 0) out.limiting_median_um = s.after[static_cast<size_t>(limiting)].median;
  for (size_t w = 0; w < s.without.size(); ++w) {
    SourceEffect e{s.without[w], s.after_without[w][static_cast<size_t>(overall)].median,
                   limiting >= 0 ? s.after_without[w][static_cast<size_t>(limiting)].median : 0.0};
    out.without.push_back(e);
  }
  // Dominant: the lowest class without it; among equals the lowest limiting median without it.
  const auto best = std::min_element(out.without.begin(), out.without.end(), [](const SourceEffect& a, const SourceEffect& b) {
    return a.overall_class != b.overall_class ? a.overall_class < b.overall_class : a.limiting_median_um < b.limiting_median_um;
  });
  out.dominant = best->source;
  return out;
}

std::string gear_record(const gears::GearSpec& spec) {
  return fmt::format("teeth={} normal_module_mm={:.9g} normal_pressure_angle_deg={:.9g} helix_angle_deg={:.9g} "
                     "profile_shift={:.9g} face_width_mm={:.9g}",
                     spec.teeth, spec.normal_module_mm, units::deg_from_rad(spec.normal_pressure_angle_rad),
                     units::deg_from_rad(spec.helix_angle_rad), spec.profile_shift, spec.face_width_mm);
}

std::string scene_fingerprint(const workbench::Workbench& wb, const std::string& options) {
  std::uint64_t h = 14695981039346656037ull; // FNV-1a 64 offset basis
  const auto add = [&h](std::string_view bytes) {
    for (const char c : bytes) {
      h ^= static_cast<unsigned char>(c);
      h *= 1099511628211ull; // FNV-1a 64 prime
    }
    h ^= 0xff; // a separator, so ("ab", "c") and ("a", "bc") differ
    h *= 1099511628211ull;
  };
  add(input::read_input_file(wb.scene.source, input::kMaxSceneBytes, "scene file"));
  for (const auto& table : wb.scene.machine.table_files)
    add(input::read_input_file(table, input::kMaxErrorTableBytes, "error table"));
  add(options);
  return fmt::format("{:016x}", h);
}

} // namespace geartopo::pipeline
