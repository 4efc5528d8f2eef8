#include "app/options.hpp"
#include "geartopo/core/text_field.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/pipeline/pipeline.hpp"
#include "geartopo/report/prediction_report.hpp"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <thread>
#include <utility>
#include <unistd.h>

namespace geartopo::app {

namespace {
std::atomic<bool> quiet_flag{false};

bool parse_int(const std::string& s, int& v) {
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}
} // namespace

CLI::Validator finite_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0.0;
        const char* end = text.data() + text.size();
        const auto [p, ec] = std::from_chars(text.data(), end, v);
        if (ec != std::errc() || p != end) return fmt::format("'{}' is not a number", text);
        if (!std::isfinite(v)) return fmt::format("'{}' is not a finite number", text);
        if (v < lo || v > hi) return fmt::format("{} is outside [{}, {}]", text, lo, hi);
        return {};
      },
      fmt::format("FINITE in [{}, {}]", lo, hi));
}

CLI::Validator probe_sigma_um() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        const char* end = text.data() + text.size();
        const auto [p, ec] = std::from_chars(text.data(), end, v);
        if (ec != std::errc() && ec != std::errc::result_out_of_range) return fmt::format("'{}' is not a number", text::excerpt(text));
        if (p != end) return fmt::format("'{}' is not a number", text::excerpt(text));
        if (ec == std::errc::result_out_of_range || !std::isfinite(v) || v < kMinProbeSigmaUm || v > kMaxProbeSigmaUm)
          return fmt::format("{} µm is not a probe noise σ: {:g} … {:g} µm (below {:g} µm no probe measures, and the "
                             "fit's Σr²/σ² would overflow)",
                             text::excerpt(text), kMinProbeSigmaUm, kMaxProbeSigmaUm, kMinProbeSigmaUm);
        return {};
      },
      fmt::format("σ in [{:g}, {:g}] µm", kMinProbeSigmaUm, kMaxProbeSigmaUm));
}

CLI::Validator non_empty_path() {
  return CLI::Validator([](std::string& text) -> std::string { return text.empty() ? "an empty path" : ""; }, "PATH");
}

CLI::Validator seed_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
          return fmt::format("'{}' is not a whole number of 0 … 2⁶⁴ − 1", text::excerpt(text));
        // CLI11 would wrap 2⁶⁴ to 0 (and anything larger to something else): a seed must be what was written.
        std::uint64_t v = 0;
        if (text::parse_number(text, v) != std::errc())
          return fmt::format("'{}' is beyond 2⁶⁴ − 1 = {}, the largest seed", text::excerpt(text),
                             std::numeric_limits<std::uint64_t>::max());
        return {};
      },
      "UINT64");
}

void refuse_paper_on_a_designed_helix(const std::string& method, const workbench::Workbench& wb) {
  if (method == "paper" && wb.design_motion)
    throw CLI::ValidationError("--method", "paper drives the wheel to its nominal pose and would grind away the drawing's "
                                           "helix modifications (gear.modifications): use flank or cycle, which correct "
                                           "towards the design");
}

std::string compensation_made_worse(double before_um, double after_um) {
  if (!(after_um > before_um + kWorseToleranceUm)) return {};
  // A percentage of a "before" that is zero within the simulation's rounding is meaningless (finding 20).
  const std::string growth = before_um > kWorseToleranceUm
                                 ? fmt::format("{:+.3f} µm, {:+.1f} %", after_um - before_um, 100.0 * (after_um - before_um) / before_um)
                                 : fmt::format("{:+.3f} µm from a gear that was perfect", after_um - before_um);
  return fmt::format("compensation made the gear worse even in the model: nominal (the model corrected by itself), the "
                     "largest |deviation| grows from {:.3f} to {:.3f} µm ({}); do not apply these corrections (try the "
                     "other --method)",
                     before_um, after_um, growth);
}

namespace {
/// The cause of a worse after-state, as the decomposition by source measured it (pipeline::after_limit): "without the
/// rounding to machine.resolution the median class is 4 (f_fβ 6.33 → 0.56 µm): it sets the class", or, when the
/// samples were exact (no decomposition), that it was not measured.
std::string measured_cause(const pipeline::MonteCarloSummary& p) {
  const auto limit = pipeline::after_limit(p);
  if (!limit.measured)
    return "the cause was not measured (exact samples: no decomposition by source); check machine.resolution against "
           "the corrections and the uncertainties before applying them";
  for (const auto& w : limit.without)
    if (w.source == limit.dominant)
      return fmt::format("without {} the median class is {:g} ({} {:.2f} → {:.2f} µm): it sets the class after",
                         report::source_label(w.source), w.overall_class, report::quantity_label(limit.limiting_quantity),
                         limit.limiting_median_um, w.limiting_median_um);
  return {};
}
} // namespace

std::string prediction_made_worse(const pipeline::MonteCarloSummary& p) {
  const int cls = p.find("overall_class"), largest = p.find("largest_abs_um");
  if (cls >= 0 && p.after[static_cast<size_t>(cls)].median > p.before[static_cast<size_t>(cls)].median)
    return fmt::format("the predicted gear is worse after compensation: overall class {:g} against {:g} before (medians of "
                       "{} samples); {}",
                       p.after[static_cast<size_t>(cls)].median, p.before[static_cast<size_t>(cls)].median, p.samples,
                       measured_cause(p));
  // Medians of a few dozen samples scatter: only an after-median above the whole 95 % interval before is "worse".
  if (largest >= 0 && p.after[static_cast<size_t>(largest)].median > p.before[static_cast<size_t>(largest)].high)
    return fmt::format("the predicted gear is worse after compensation: largest |deviation| {:.2f} µm (median) against "
                       "{:.2f} µm [{:.2f}, {:.2f}] before ({} samples); {}",
                       p.after[static_cast<size_t>(largest)].median, p.before[static_cast<size_t>(largest)].median,
                       p.before[static_cast<size_t>(largest)].low, p.before[static_cast<size_t>(largest)].high, p.samples,
                       measured_cause(p));
  return {};
}

namespace {
// A stream buffer that accepts everything and keeps nothing.
class NullBuffer : public std::streambuf {
protected:
  int overflow(int c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};
} // namespace

JsonSummary::JsonSummary(bool enabled) {
  if (!enabled) return;
  sink_ = std::make_unique<NullBuffer>();
  saved_ = std::cout.rdbuf(sink_.get());
}

JsonSummary::~JsonSummary() {
  if (saved_ != nullptr) std::cout.rdbuf(saved_);
}

void JsonSummary::emit(const nlohmann::json& summary) {
  if (saved_ == nullptr) return;
  std::cout.rdbuf(saved_);
  saved_ = nullptr;
  std::cout << summary.dump(2) << "\n";
}

void set_quiet(bool q) { quiet_flag = q; }
bool quiet() { return quiet_flag; }

namespace {
struct HeldMessages {
  std::mutex mutex;
  bool holding = false;
  std::string text;
};
HeldMessages& held_messages() {
  static HeldMessages h;
  return h;
}
} // namespace

void hold_messages() {
  auto& h = held_messages();
  const std::lock_guard lock(h.mutex);
  h.holding = true;
}

void say(std::string_view line) {
  auto& h = held_messages();
  const std::lock_guard lock(h.mutex);
  if (h.holding) {
    h.text.append(line).append("\n");
    return;
  }
  std::fputs((std::string(line) + "\n").c_str(), stderr);
  std::fflush(stderr);
}

void release_messages() {
  auto& h = held_messages();
  const std::lock_guard lock(h.mutex);
  if (!h.text.empty()) std::fputs(h.text.c_str(), stderr);
  std::fflush(stderr);
  h.text.clear();
  h.holding = false;
}

std::string take_held_messages() {
  auto& h = held_messages();
  const std::lock_guard lock(h.mutex);
  h.holding = false;
  return std::exchange(h.text, {});
}

struct Progress::State {
  std::string what, unit;
  std::atomic<long long> total{0}, done{0};
  // `active` is read by every worker before it takes the lock (the cheap early return) and cleared by finish():
  // atomic, so that read is not a data race. `shown` and `last` are touched only under `mutex`.
  std::atomic<bool> active{false};
  bool shown = false;
  std::mutex mutex;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now(), last;
};

Progress::Progress(std::string what, long long total, std::string unit) : state_(std::make_unique<State>()) {
  state_->what = std::move(what);
  state_->unit = std::move(unit);
  state_->total = total;
  state_->active = !quiet() && ::isatty(STDERR_FILENO) != 0;
  if (state_->active && total <= 0) { // no count yet: the stage's name, until a count or the next line replaces it
    release_messages();
    std::fputs(fmt::format("\rgeartopo: {} …\033[K", state_->what).c_str(), stderr);
    std::fflush(stderr);
    state_->shown = true;
  }
}

Progress::~Progress() { finish(); }

void Progress::finish() {
  const std::lock_guard lock(state_->mutex);
  if (state_->shown) std::fputs("\r\033[K", stderr);
  state_->shown = false;
  state_->active = false;
}

void Progress::advance(long long n) {
  long long done = state_->done += n;
  const long long total = state_->total;
  if (!state_->active || total <= 0) return;
  // The last unit waits for the line (it must show "total/total"); the others skip it while another worker prints.
  std::unique_lock lock(state_->mutex, std::defer_lock);
  if (done >= total)
    lock.lock();
  else if (!lock.try_lock())
    return;
  if (!state_->active) return; // finished
  done = state_->done;         // a worker that waited may hold an older count
  const auto now = std::chrono::steady_clock::now();
  if (state_->shown && now - state_->last < std::chrono::milliseconds(200) && done < total) return;
  state_->last = now;
  if (!state_->shown) release_messages(); // the work has started: what was said before it goes first
  state_->shown = true;
  const double s = std::chrono::duration<double>(now - state_->start).count();
  // Time left at the rate so far (the units of one stage cost about the same: flanks, samples, fits).
  const std::string left = done > 0 && done < total
                               ? fmt::format(", about {:.0f} s left", s * static_cast<double>(total - done) / static_cast<double>(done))
                               : std::string();
  std::fputs(fmt::format("\rgeartopo: {} {}/{} {}, {:.0f} s{}\033[K", state_->what, std::min(done, total), total,
                         state_->unit, s, left)
                 .c_str(),
             stderr);
  std::fflush(stderr);
}

void Progress::update(long long done, long long total) {
  // Raise the total to `total` if larger; a compare-exchange loop, so two workers reporting at once keep the larger.
  long long known = state_->total.load();
  while (total > known && !state_->total.compare_exchange_weak(known, total)) {
  }
  const long long before = state_->done.load();
  if (done > before) advance(done - before);
}

std::function<void(long long, long long)> Progress::callback() {
  return [this](long long done, long long total) { update(done, total); };
}

MonteCarloWatch::MonteCarloWatch(long long samples, int threads, double max_seconds, std::string split_hint, bool adaptive)
    : samples_(samples),
      adaptive_(adaptive),
      threads_(static_cast<int>(std::min<long long>(
          samples, threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency())))),
      max_seconds_(max_seconds),
      split_hint_(std::move(split_hint)),
      progress_(pipeline::kPredictionStage, samples, "samples") {}

void MonteCarloWatch::prepared() {
  if (any_done_ || prepared_) return; // the first preparation only (an MPI rank prepares each adaptive batch)
  const auto now = std::chrono::steady_clock::now();
  preparation_s_ = std::chrono::duration<double>(now - start_).count();
  start_ = now;
  prepared_ = true;
}

void MonteCarloWatch::sample_done(long long done, long long total) {
  any_done_ = true;
  if (done == 1) { // the first sample: every thread started one at the same time, this one finished first
    const double first = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const long long rounds = (samples_ + threads_ - 1) / std::max(1, threads_);
    const double estimate = preparation_s_ + first * static_cast<double>(rounds);
    const std::string what = fmt::format("{} samples at {:.2g} s each on {} thread(s){}: about {:.{}f} s{}", samples_, first,
                                         threads_,
                                         prepared_ ? fmt::format(" after {:.2g} s of preparation", preparation_s_) : "",
                                         estimate, estimate < 10.0 ? 1 : 0,
                                         adaptive_ ? " at most (the adaptive run may stop earlier)" : "");
    if (estimate > max_seconds_)
      throw CLI::ValidationError("--samples", fmt::format("the Monte Carlo prediction would take too long: {}, beyond "
                                                          "the limit of {:g} s (--max-time-s): use fewer --samples or {}",
                                                          what, max_seconds_, split_hint_));
    if (!quiet() && ::isatty(STDERR_FILENO) != 0) {
      release_messages();
      std::fputs(fmt::format("\r\033[Kgeartopo: Monte Carlo: {}\n", what).c_str(), stderr);
    }
  }
  progress_.update(done, total);
}

std::function<void(long long, long long)> MonteCarloWatch::callback() {
  return [this](long long done, long long total) { sample_done(done, total); };
}

void finish_output_folder(output::OutputFolder& folder) {
  const auto removed = folder.finish();
  if (quiet()) return;
  for (const auto& t : folder.removed_temporaries())
    say(fmt::format("geartopo: removed {}, left by an interrupted geartopo run", (folder.path() / t).string()));
  if (!removed.empty()) {
    std::vector<std::string> names;
    for (const auto& r : removed) names.push_back(r.generic_string());
    say(fmt::format("geartopo: removed {} file(s) an earlier run wrote into {} and this one did not: {}", removed.size(),
                    folder.path().string(), fmt::join(names, ", ")));
  }
}

void print_notes(const workbench::Workbench& wb) {
  if (quiet()) return;
  for (const auto& n : wb.notes) say("geartopo: note: " + n);
}

void print_work_estimate(long long points, long long flanks, bool exact, int passes) {
  if (points < kEstimateFromPoints || quiet()) return;
  const double rate = exact ? 1.5e6 : 2.9e6; // points/s, 2 cores (docs/performance.md, "Against the targets")
  const std::string times = passes > 1 ? fmt::format(", {} times", passes) : std::string();
  const double seconds = static_cast<double>(points) * passes / rate;
  release_messages(); // long work: its estimate is seen now, what was said before it first
  std::fprintf(stderr, "geartopo: %s\n",
               fmt::format("{} points on {} flanks ({}{}): about {:.{}f} s on 2 cores", points, flanks,
                           exact ? "exact" : "linear", times, seconds, seconds < 10.0 ? 1 : 0)
                   .c_str());
}

SimulationWatch::SimulationWatch(std::string stage, long long flanks, int threads, double max_seconds,
                                 std::chrono::steady_clock::time_point job_start, std::string hint)
    : stage_(std::move(stage)),
      flanks_(flanks),
      threads_(static_cast<int>(std::max<long long>(
          1, std::min<long long>(flanks, threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency()))))),
      max_seconds_(max_seconds),
      job_start_(job_start),
      hint_(std::move(hint)),
      progress_(stage_, flanks, "flanks") {}

void SimulationWatch::flank_done(long long done, long long total) {
  if (done == 1 && flanks_ > 1) { // the first flank: every thread started one at the same time, this one finished first
    const auto now = std::chrono::steady_clock::now();
    const double first = std::chrono::duration<double>(now - start_).count();
    const double spent = std::chrono::duration<double>(now - job_start_).count();
    const long long rounds = (flanks_ + threads_ - 1) / threads_;
    const double estimate = first * static_cast<double>(rounds);
    const std::string what = fmt::format("{} {} flanks at {:.2g} s each on {} thread(s): about {:.{}f} s", stage_, flanks_,
                                         first, threads_, estimate, estimate < 10.0 ? 1 : 0);
    if (spent - first + estimate > max_seconds_)
      throw CLI::ValidationError("--max-time-s", fmt::format("the job would take too long: {}{}, beyond the limit of {:g} s "
                                                             "(--max-time-s): use {}",
                                                             what,
                                                             spent - first > 1.0
                                                                 ? fmt::format(" after {:.0f} s already spent", spent - first)
                                                                 : std::string(),
                                                             max_seconds_, hint_));
    if (!quiet() && estimate >= kPrintEstimateFromSeconds) {
      release_messages();
      std::fputs(fmt::format("{}geartopo: {}\n", ::isatty(STDERR_FILENO) != 0 ? "\r\033[K" : "", what).c_str(), stderr);
    }
  }
  progress_.update(done, total);
}

std::function<void(long long, long long)> SimulationWatch::callback() {
  return [this](long long done, long long total) { flank_done(done, total); };
}

std::vector<int> parse_teeth(const std::string& text, int teeth) {
  // "" used to mean all teeth: an empty list is far more likely a script's empty variable than a wish for all.
  if (text.empty()) throw CLI::ValidationError("--teeth", "an empty list (use e.g. 1,18 or all)");
  if (text == "all") return {};
  std::vector<int> out;
  size_t start = 0;
  for (;;) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    int v = 0;
    if (!parse_int(item, v) || v < 1 || v > teeth)
      throw CLI::ValidationError("--teeth", fmt::format("'{}' is not a tooth number of 1..{} (use e.g. 1,18 or all)", item, teeth));
    if (std::find(out.begin(), out.end(), v) != out.end())
      throw CLI::ValidationError("--teeth", fmt::format("tooth {} is listed twice", v));
    out.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::pair<int, int> parse_grid_size(const std::string& text) {
  const auto x = text.find('x');
  int r = 0, c = 0;
  if (x == std::string::npos || !parse_int(text.substr(0, x), r) || !parse_int(text.substr(x + 1), c) || r < 2 || c < 2 ||
      static_cast<long long>(r) * c > grinding::kMaxPointsPerFlank)
    throw CLI::ValidationError("--dense", fmt::format("'{}' is not ROWSxCOLS with 2 ≤ each and at most {} points per flank",
                                                      text, grinding::kMaxPointsPerFlank));
  return {r, c};
}

namespace {

// A word option bound to an enum: a word not in `words` is refused naming the words allowed ("'radius' is not one of
// roll-length, diameter"), not with CLI11's text of its internal map.
// The --mka-… flags given on this command line (their names), for refuse_mka_flags_without_export.
std::vector<std::string>& mka_flags_given() {
  static std::vector<std::string> given;
  return given;
}

template <class E>
void add_word_option(CLI::App* cmd, const std::string& name, E& target, std::vector<std::pair<std::string, E>> words,
                     const std::string& help, std::vector<std::string>* given = nullptr) {
  std::vector<std::string> names;
  for (const auto& [w, e] : words) names.push_back(w);
  const std::string allowed = fmt::format("{}", fmt::join(names, ", "));
  cmd->add_option_function<std::string>(
         name,
         [&target, words, given, name](const std::string& word) {
           for (const auto& [w, e] : words)
             if (w == word) target = e;
           if (given != nullptr) given->push_back(name);
         },
         help)
      ->check(CLI::Validator(
          [names, allowed](std::string& word) -> std::string {
            if (std::find(names.begin(), names.end(), word) != names.end()) return {};
            return fmt::format("'{}' is not one of {}", text::excerpt(word), allowed);
          },
          "", "word"))
      ->option_text(fmt::format("{}", fmt::join(names, "|")));
}

} // namespace

void add_klingelnberg_options(CLI::App* cmd, measurement::KlingelnbergOptions& o) {
  using measurement::DeviationDirection;
  using measurement::ProfileSpacing;
  using measurement::SignConvention;
  add_word_option<ProfileSpacing>(cmd, "--mka-spacing", o.spacing,
                                  {{"roll-length", ProfileSpacing::RollLength}, {"diameter", ProfileSpacing::Diameter}},
                                  "Klingelnberg export: profile points evenly in roll-length (default) or diameter",
                                  &mka_flags_given());
  add_word_option<DeviationDirection>(
      cmd, "--mka-direction", o.direction,
      {{"transverse", DeviationDirection::Transverse}, {"normal", DeviationDirection::Normal}},
      "Klingelnberg export: deviations transverse (default; × cos β_b to the normal) or normal", &mka_flags_given());
  add_word_option<SignConvention>(cmd, "--mka-signs", o.signs, {{"raw", SignConvention::Raw}, {"din", SignConvention::Din}},
                                  "Klingelnberg export: raw probe sign (default; profile left and helix × −1) or din "
                                  "(plus material)",
                                  &mka_flags_given());
}

void add_iso_options(CLI::App* cmd, workbench::IsoOptions& o) {
  // Through the words (evaluation's parse_… functions): CLI11 cannot bind these enums directly, their to_string
  // overloads (string_view) confuse its default-value printing.
  cmd->add_option_function<std::string>(
         "--iso-direction", [&o](const std::string& w) { o.direction = *evaluation::parse_iso_direction(w); },
         "ISO 1328-1 profile/helix deviations transverse (default: the standard's, normal / cos β_b) or normal")
      ->check(CLI::IsMember({"transverse", "normal"}))
      ->option_text("transverse|normal");
  cmd->add_option_function<std::string>(
         "--helix-slope-sign", [&o](const std::string& w) { o.helix_slope_sign = *evaluation::parse_helix_slope_sign(w); },
         "Sign of f_Hβ: helix-angle (default; > 0 when the helix angle is larger than designed) or "
         "rise-towards-plus-z (> 0 when material rises away from the datum face)")
      ->check(CLI::IsMember({"helix-angle", "rise-towards-plus-z"}))
      ->option_text("helix-angle|rise-towards-plus-z");
}

void add_measurement_options(CLI::App* cmd, std::string& file, measurement::KlingelnbergOptions& options, bool required) {
  cmd->add_option("--measured", file,
                  std::string("Measurement: topology CSV (µm), traces CSV, point cloud x_mm,y_mm,z_mm[,id] or Klingelnberg "
                              "export (docs/measurement-formats.md); told apart by content") +
                      (required ? "" : "; default: the scene's measurement.measured (none: no comparison)"))
      ->required(required);
  add_klingelnberg_options(cmd, options);
}

void refuse_mka_flags_without_export(const std::string& file) {
  if (mka_flags_given().empty()) return;
  if (file.empty())
    throw CLI::ValidationError(mka_flags_given().front(),
                               "has no effect: no measurement is read (give --measured, or measurement.measured in the "
                               "scene)");
  std::ifstream in(file, std::ios::binary); // unreadable: the reader says why
  if (!in || measurement::looks_like_klingelnberg(in)) return;
  throw CLI::ValidationError(mka_flags_given().front(),
                             fmt::format("has no effect: {} is not a Klingelnberg export (the --mka-… options read "
                                         "exports only)",
                                         file));
}

std::vector<measurement::MeasuredPoint> read_measured_points(const workbench::Workbench& wb, const std::string& file,
                                                             const measurement::KlingelnbergOptions& options,
                                                             measurement::ReadCounts* counts) {
  refuse_mka_flags_without_export(file);
  std::vector<std::string> warnings;
  auto points = measurement::read_any_measurement(file, wb.setup, &warnings, options, counts);
  for (const auto& w : warnings) say("geartopo: warning: " + w);
  return points;
}

} // namespace geartopo::app
