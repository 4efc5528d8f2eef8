#include "geartopo/report/improvement.hpp"
#include "geartopo/report/prediction_report.hpp"

#include <fmt/format.h>

#include <cmath>

namespace geartopo::report {
namespace {

/// A percentage of a before-median this small is noise (the ISO values are reported to 0.01 µm).
constexpr double kSmallestBeforeUm = 0.01;

bool is_size(const std::string& name) {
  const bool um = name.size() > 3 && name.compare(name.size() - 3, 3, "_um") == 0;
  return um && name != "thickness_um" && name != "rotation_um"; // signed: "less" is not "better"
}

} // namespace

std::vector<Improvement> predicted_improvement(const pipeline::MonteCarloSummary& p) {
  std::vector<Improvement> out;
  for (size_t i = 0; i < p.names.size(); ++i) {
    const double b = p.before[i].median;
    if (!is_size(p.names[i]) || !(b > kSmallestBeforeUm)) continue;
    const auto& a = p.after[i];
    const auto pct = [b](double after) { return 100.0 * (b - after) / b; };
    out.push_back({p.names[i], b, a, pct(a.median), pct(a.high), pct(a.low)});
  }
  return out;
}

std::vector<Worsening> predicted_worsening(const pipeline::MonteCarloSummary& p) {
  std::vector<Worsening> out;
  for (const auto& i : predicted_improvement(p)) {
    if (!(i.after_um.median > i.before_median_um)) continue;
    Worsening w{i.name, i.before_median_um, i.after_um.median, {}, 0.0};
    const int k = p.find(i.name);
    for (size_t s = 0; s < p.without.size() && s < p.after_without.size(); ++s) {
      const double m = p.after_without[s][static_cast<size_t>(k)].median;
      if (w.source.empty() || m < w.without_source_median_um) w.source = p.without[s], w.without_source_median_um = m;
    }
    out.push_back(std::move(w));
  }
  return out;
}

namespace {
/// What a source does to the gear after compensation, where it is not plain from its name.
std::string mechanism(const std::string& source) {
  if (source == "resolution_rounding")
    return " — the corrections of the axes a stroke holds still (X, Y, A) step by whole command units along it, and "
           "a helical flank's inclined contact line carries each step across the profile (docs/compensation.md, "
           "\"Command resolution\")";
  if (source == "repeatability") return " — each stroke's scatter, which no correction removes";
  return {};
}
} // namespace

std::string worsening_text(const Worsening& w) {
  const std::string head =
      fmt::format("{} {:.2f} → {:.2f} µm", quantity_label(w.name), w.before_median_um, w.after_median_um);
  if (w.source.empty()) return head + ": the cause was not measured (exact samples carry no decomposition by source)";
  const std::string verdict = w.without_source_median_um <= w.before_median_um ? "" : " (still above before: no single "
                                                                                       "source explains it)";
  return fmt::format("{}: without {} {:.2f} µm{}{}", head, source_label(w.source), w.without_source_median_um, verdict,
                     mechanism(w.source));
}

nlohmann::json improvement_json(const pipeline::MonteCarloSummary& p) {
  nlohmann::json q = nlohmann::json::object();
  for (const auto& i : predicted_improvement(p))
    q[i.name] = {{"before_median_um", i.before_median_um}, {"after_median_um", i.after_um.median},
                 {"after_low_um", i.after_um.low},         {"after_high_um", i.after_um.high},
                 {"improvement_percent", i.percent},       {"improvement_low_percent", i.low_percent},
                 {"improvement_high_percent", i.high_percent}};
  for (const auto& w : predicted_worsening(p)) {
    q[w.name]["worse"] = {{"source", w.source}, {"text", worsening_text(w)}};
    if (!w.source.empty()) q[w.name]["worse"]["after_median_without_source_um"] = w.without_source_median_um;
  }
  return {{"definition", kImprovementDefinition}, {"samples", p.samples}, {"quantities", q}};
}

namespace {
// "−0" reads oddly: values that round to zero are written 0.
std::string whole(double v) { return std::abs(v) < 0.5 ? std::string("0") : fmt::format("{:.0f}", v); }
} // namespace

std::string improvement_text(const Improvement& i) {
  return fmt::format("{} % [{}, {}]", whole(i.percent), whole(i.low_percent), whole(i.high_percent));
}

std::string improvement_number_text(const Improvement& i) {
  return fmt::format("{} [{}, {}]", whole(i.percent), whole(i.low_percent), whole(i.high_percent));
}

std::vector<std::string> improvement_lines(const pipeline::MonteCarloSummary& p) {
  std::vector<std::string> out;
  // (through fmt: GCC 12 warns falsely, -Warray-bounds, on a long literal pushed into a vector of strings)
  out.push_back(fmt::format("Predicted improvement of the medians, {} samples [the after-state's 95 % interval against the "
                            "before-median]; negative: worse",
                            p.samples));
  for (const auto& i : predicted_improvement(p))
    out.push_back(fmt::format("  {:<22} {}", quantity_label(i.name), improvement_text(i)));
  for (const auto& w : predicted_worsening(p)) out.push_back("  worse after compensation: " + worsening_text(w));
  return out;
}

} // namespace geartopo::report
