// A Monte Carlo run's samples as a CSV file (write_run_csv, read_run_csv: monte_carlo.hpp): what a shard writes and
// `geartopo merge` reads. Comment lines carry the run's settings; then a header and one row per sample.
#include "geartopo/pipeline/monte_carlo.hpp"

#include "quantity_names.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/core/text_field.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/input_file.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <sstream>

namespace geartopo::pipeline {

namespace {

/// A partial result read line by line: the settings' comment lines, then the header, then the samples.
class RunCsvReader {
public:
  explicit RunCsvReader(std::string name) : name_(std::move(name)) { run_.source = name_; }
  MonteCarloRun read(const std::string& text);

private:
  [[noreturn]] void fail(int column, const std::string& field, const std::string& message) const {
    throw InputError(SourcePosition{name_, line_no_, column}, field, message);
  }
  /// The key's value when `view_` starts with the key ("# seed: "), else nullopt.
  std::optional<std::string_view> value_of(std::string_view key) const;
  /// The column of the key's value, and the key's field name ("# seed: " → "seed").
  static int value_column(std::string_view key) { return static_cast<int>(key.size()) + 1; }
  static std::string field_of(std::string_view key) { return std::string(key.substr(2, key.size() - 4)); }

  void read_comment();
  /// A whole number after `key`; `have` set when the key is there.
  template <class T>
  void read_whole(std::string_view key, T& value, bool& have);
  /// A number ≥ 0 after `key`.
  void read_non_negative(std::string_view key, double& value);
  /// One of `words` after `key`.
  void read_word(std::string_view key, std::initializer_list<std::string_view> words, std::string& value);
  /// An ISO option's word after `key`, read by `parse`. Absent in files written before they were recorded (compensate
  /// then always used the defaults).
  template <class Parse, class T>
  void read_iso_word(std::string_view key, Parse parse, T& value);
  void read_fingerprint_and_gear();

  std::vector<std::string_view> fields() const;
  void read_header(const std::vector<std::string_view>& f);
  /// The header's groups: before.*, after.*, without_<source>.* …, each with its names.
  void read_groups(const std::vector<std::string_view>& f, std::vector<std::string>& groups,
                   std::vector<std::vector<std::string>>& group_names) const;
  void read_sample(const std::vector<std::string_view>& f);
  int column_of(const std::vector<std::string_view>& f, size_t i) const {
    return static_cast<int>(f[i].data() - view_.data()) + 1;
  }

  std::string name_;
  MonteCarloRun run_;
  bool have_total_ = false, have_seed_ = false, have_header_ = false;
  std::vector<detail::QuantityRule> rules_; // per name
  int line_no_ = 0;
  std::string_view view_; // the line being read
};

MonteCarloRun RunCsvReader::read(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    ++line_no_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    view_ = line;
    if (line_no_ == 1) text::strip_bom(view_);
    if (view_.empty()) continue;
    if (view_.front() == '#') {
      read_comment();
      continue;
    }
    const auto f = fields();
    if (!have_header_)
      read_header(f);
    else
      read_sample(f);
  }
  if (!have_header_) fail(0, "header", "no header line (sample,before.…): not a partial result");
  return std::move(run_);
}

std::optional<std::string_view> RunCsvReader::value_of(std::string_view key) const {
  if (view_.substr(0, key.size()) != key) return std::nullopt;
  return view_.substr(key.size());
}

template <class T>
void RunCsvReader::read_whole(std::string_view key, T& value, bool& have) {
  const auto rest = value_of(key);
  if (!rest) return;
  if (text::parse_number(*rest, value) != std::errc())
    fail(value_column(key), field_of(key),
         key == "# seed: " ? fmt::format("'{}' is not a seed: a whole number of 0 … 2⁶⁴ − 1", text::excerpt(*rest))
                           : fmt::format("'{}' is not a whole number", text::excerpt(*rest)));
  have = true;
}

void RunCsvReader::read_non_negative(std::string_view key, double& value) {
  const auto rest = value_of(key);
  if (!rest) return;
  if (text::parse_number(*rest, value) != std::errc() || !std::isfinite(value) || value < 0.0)
    fail(value_column(key), field_of(key), fmt::format("'{}' is not a number ≥ 0", text::excerpt(*rest)));
}

void RunCsvReader::read_word(std::string_view key, std::initializer_list<std::string_view> words, std::string& value) {
  const auto rest = value_of(key);
  if (!rest) return;
  if (std::find(words.begin(), words.end(), *rest) == words.end())
    fail(value_column(key), field_of(key),
         fmt::format("'{}' is not one of the words geartopo writes", text::excerpt(*rest)));
  value = std::string(*rest);
}

template <class Parse, class T>
void RunCsvReader::read_iso_word(std::string_view key, Parse parse, T& value) {
  const auto rest = value_of(key);
  if (!rest) return;
  const auto parsed = parse(*rest);
  if (!parsed)
    fail(value_column(key), field_of(key),
         fmt::format("'{}' is not one of the words geartopo writes", text::excerpt(*rest)));
  value = *parsed;
}

void RunCsvReader::read_comment() {
  // "# key: value": where each setting stands, for merge_runs' refusals
  if (const auto colon = view_.find(": "); view_.starts_with("# ") && colon != std::string_view::npos)
    run_.lines[std::string(view_.substr(2, colon - 2))] = line_no_;
  read_whole("# samples_total: ", run_.samples_total, have_total_);
  read_whole("# seed: ", run_.seed, have_seed_);
  if (const auto rest = value_of("# probe_noise_um: ")) {
    if (text::parse_number(*rest, run_.probe_noise_um) != std::errc() || !std::isfinite(run_.probe_noise_um) ||
        run_.probe_noise_um < 0.0)
      fail(value_column("# probe_noise_um: "), "probe_noise_um",
           fmt::format("'{}' is not a σ ≥ 0 (µm)", text::excerpt(*rest)));
  }
  read_non_negative("# linear_check_points_um: ", run_.sampling.largest_point_difference_um);
  read_non_negative("# linear_check_quantities_um: ", run_.sampling.largest_quantity_difference_um);
  bool have_checked = false;
  read_whole("# linear_check_samples: ", run_.sampling.checked_samples, have_checked);
  read_word("# sampling: ", {"linear", "exact"}, run_.sampling.method);
  read_word("# sampling_reason: ", {"checked", "check failed", "forced", "unchecked", ""}, run_.sampling.reason);
  read_fingerprint_and_gear();
  read_iso_word("# iso_direction: ", evaluation::parse_iso_direction, run_.iso.direction);
  read_iso_word("# helix_slope_sign: ", evaluation::parse_helix_slope_sign, run_.iso.helix_slope_sign);
}

void RunCsvReader::read_fingerprint_and_gear() {
  if (const auto rest = value_of("# scene_fingerprint: ")) {
    if (rest->size() != 16 || rest->find_first_not_of("0123456789abcdef") != std::string_view::npos)
      fail(value_column("# scene_fingerprint: "), "scene_fingerprint",
           fmt::format("'{}' is not a fingerprint geartopo writes (16 hex digits, 0-9 a-f)", text::excerpt(*rest)));
    run_.scene_fingerprint = std::string(*rest);
  }
  if (const auto rest = value_of("# gear: ")) {
    if (!rest->starts_with("teeth=") || rest->size() > 200)
      fail(value_column("# gear: "), "gear",
           fmt::format("'{}' is not a gear record geartopo writes ('teeth=… normal_module_mm=…')", text::excerpt(*rest)));
    run_.gear = std::string(*rest);
  }
}

std::vector<std::string_view> RunCsvReader::fields() const {
  std::vector<std::string_view> out;
  for (size_t start = 0;;) {
    const auto comma = view_.find(',', start);
    out.push_back(view_.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

void RunCsvReader::read_groups(const std::vector<std::string_view>& f, std::vector<std::string>& groups,
                               std::vector<std::vector<std::string>>& group_names) const {
  for (size_t i = 1; i < f.size(); ++i) {
    const auto dot = f[i].find('.');
    if (dot == std::string_view::npos) fail(column_of(f, i), "header", "expected <group>.<name>");
    const std::string group(f[i].substr(0, dot));
    if (groups.empty() || groups.back() != group) groups.push_back(group), group_names.emplace_back();
    group_names.back().emplace_back(f[i].substr(dot + 1));
  }
}

void RunCsvReader::read_header(const std::vector<std::string_view>& f) {
  if (!have_total_ || !have_seed_) fail(1, "header", "'# samples_total: M' and '# seed: S' must come before the header");
  if (run_.samples_total < 1) fail(1, "samples_total", "must be ≥ 1");
  // sample, then groups of the same names in the same order: before.*, after.*, without_<source>.* …
  if (f.empty() || f[0] != "sample") fail(1, "header", "expected sample,before.<name>,…,after.<name>,…");
  std::vector<std::string> groups;
  std::vector<std::vector<std::string>> group_names;
  read_groups(f, groups, group_names);
  if (groups.size() < 2 || groups[0] != "before" || groups[1] != "after")
    fail(1, "header", "expected sample,before.<name>,…,after.<name>,…");
  for (size_t k = 1; k < groups.size(); ++k) {
    if (group_names[k] != group_names[0])
      fail(1, "header", fmt::format("the names of '{}' are not those of 'before' in the same order", groups[k]));
    if (k < 2) continue;
    const auto& sources = limit_sources();
    const std::string source = groups[k].substr(std::string_view("without_").size());
    if (!groups[k].starts_with("without_") || std::find(sources.begin(), sources.end(), source) == sources.end())
      fail(1, "header", fmt::format("'{}' is not a group geartopo writes (without_<source>)", groups[k]));
    run_.without.push_back(source);
  }
  run_.names = group_names[0];
  run_.lines["header"] = line_no_;
  for (size_t n = 0; n < run_.names.size(); ++n) {
    const auto rule = detail::rule_of(run_.names[n]);
    if (!rule)
      fail(column_of(f, 1 + n), "header",
           fmt::format("'{}' is not a quantity geartopo writes ({})", text::excerpt(run_.names[n]),
                       fmt::join(detail::known_quantity_names(), ", ")));
    const auto before = run_.names.begin() + static_cast<std::ptrdiff_t>(n);
    if (std::find(run_.names.begin(), before, run_.names[n]) != before)
      fail(column_of(f, 1 + n), "header", fmt::format("'{}' is listed twice", run_.names[n]));
    rules_.push_back(*rule);
  }
  have_header_ = true;
}

void RunCsvReader::read_sample(const std::vector<std::string_view>& f) {
  const size_t groups = 2 + run_.without.size(), names = run_.names.size();
  if (f.size() != 1 + groups * names) fail(1, "sample", fmt::format("{} fields, the header has {}", f.size(), 1 + groups * names));
  MonteCarloSample s;
  if (text::parse_number(f[0], s.index) != std::errc() || s.index < 0 || s.index >= run_.samples_total)
    fail(1, "sample", fmt::format("'{}' is not a sample number of this run of {} samples (0 … {})", text::excerpt(f[0]),
                                  run_.samples_total, run_.samples_total - 1));
  s.after_without.resize(run_.without.size());
  for (size_t i = 1; i < f.size(); ++i) {
    const size_t group = (i - 1) / names, n = (i - 1) % names;
    const std::string field =
        (group == 0 ? "before." : group == 1 ? "after." : "without_" + run_.without[group - 2] + ".") + run_.names[n];
    double v = 0.0;
    if (text::parse_number(f[i], v) != std::errc() || !std::isfinite(v))
      fail(column_of(f, i), field, fmt::format("'{}' is not a finite number", text::excerpt(f[i])));
    if (const std::string why = rules_[n].refusal(v); !why.empty())
      fail(column_of(f, i), field, fmt::format("{} {}", text::excerpt(f[i]), why));
    (group == 0 ? s.before : group == 1 ? s.after : s.after_without[group - 2]).push_back(v);
  }
  if (!run_.samples.empty() && s.index <= run_.samples.back().index) fail(1, "sample", "sample numbers must increase");
  run_.samples.push_back(std::move(s));
}

} // namespace

void write_run_csv(const std::filesystem::path& file, const MonteCarloRun& run) {
  output::write_atomically(file, [&](std::ostream& out) {
    out << "# geartopo Monte Carlo partial result (docs/monte-carlo.md); merge with: geartopo merge\n";
    out << "# samples_total: " << run.samples_total << "\n# seed: " << run.seed << "\n";
    out << "# iso_direction: " << evaluation::to_string(run.iso.direction)
        << "\n# helix_slope_sign: " << evaluation::to_string(run.iso.helix_slope_sign) << "\n";
    out << fmt::format("# probe_noise_um: {}\n", run.probe_noise_um);
    out << "# sampling: " << run.sampling.method << "\n# sampling_reason: " << run.sampling.reason << "\n";
    out << fmt::format("# linear_check_samples: {}\n# linear_check_points_um: {}\n# linear_check_quantities_um: {}\n",
                       run.sampling.checked_samples, run.sampling.largest_point_difference_um,
                       run.sampling.largest_quantity_difference_um);
    if (!run.scene_fingerprint.empty()) out << "# scene_fingerprint: " << run.scene_fingerprint << "\n";
    if (!run.gear.empty()) out << "# gear: " << run.gear << "\n";
    out << "sample";
    for (const auto& n : run.names) out << ",before." << n;
    for (const auto& n : run.names) out << ",after." << n;
    for (const auto& w : run.without)
      for (const auto& n : run.names) out << ",without_" << w << "." << n;
    out << "\n";
    for (const auto& s : run.samples) {
      out << s.index;
      for (double v : s.before) out << fmt::format(",{}", v); // shortest form that reads back to the same double
      for (double v : s.after) out << fmt::format(",{}", v);
      for (const auto& w : s.after_without)
        for (double v : w) out << fmt::format(",{}", v);
      out << "\n";
    }
  });
}

MonteCarloRun read_run_csv(const std::filesystem::path& file) {
  const std::string text = input::read_input_file(file, input::kMaxMeasurementBytes, "Monte Carlo partial result");
  return RunCsvReader(file.string()).read(text);
}

} // namespace geartopo::pipeline
