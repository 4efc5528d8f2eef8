#include "app/measurement_options.hpp"

#include "app/messages.hpp"

#include "geartopo/core/text_field.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <fstream>
#include <utility>

namespace geartopo::app {

namespace {

// A word option bound to an enum: a word not in `words` is refused naming the words allowed ("'radius' is not one of
// roll-length, diameter"), not with CLI11's text of its internal map. The option's name is added to `given` when it
// is on the command line (when given).
template <class E>
void add_word_option(CLI::App* cmd, const std::string& name, E& target, std::vector<std::pair<std::string, E>> words,
                     const std::string& help, std::vector<std::string>* given) {
  std::vector<std::string> names;
  for (const auto& [w, e] : words) names.push_back(w);
  const std::string allowed = fmt::format("{}", fmt::join(names, ", "));
  cmd->add_option_function<std::string>(
         name,
         [&target, words, given, name](const std::string& word) {
           for (const auto& [w, e] : words)
             if (w == word) target = e;
           if (given) given->push_back(name);
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

void add_klingelnberg_options(CLI::App* cmd, KlingelnbergFlags& flags) {
  using measurement::DeviationDirection;
  using measurement::ProfileSpacing;
  using measurement::SignConvention;
  auto& o = flags.options;
  add_word_option<ProfileSpacing>(cmd, "--mka-spacing", o.spacing,
                                  {{"roll-length", ProfileSpacing::RollLength}, {"diameter", ProfileSpacing::Diameter}},
                                  "Klingelnberg export: profile points evenly in roll-length (default) or diameter",
                                  &flags.given);
  add_word_option<DeviationDirection>(
      cmd, "--mka-direction", o.direction,
      {{"transverse", DeviationDirection::Transverse}, {"normal", DeviationDirection::Normal}},
      "Klingelnberg export: deviations transverse (default; × cos β_b to the normal) or normal", &flags.given);
  add_word_option<SignConvention>(cmd, "--mka-signs", o.signs, {{"raw", SignConvention::Raw}, {"din", SignConvention::Din}},
                                  "Klingelnberg export: raw probe sign (default; profile left and helix × −1) or din "
                                  "(plus material)",
                                  &flags.given);
}

void add_measurement_options(CLI::App* cmd, std::string& file, KlingelnbergFlags& flags, bool required) {
  cmd->add_option("--measured", file,
                  std::string("Measurement: topology CSV (µm), traces CSV, point cloud x_mm,y_mm,z_mm[,id] or Klingelnberg "
                              "export (docs/measurement-formats.md); told apart by content") +
                      (required ? "" : "; default: the scene's measurement.measured (none: no comparison)"))
      ->required(required);
  add_measured_against_option(cmd, flags);
  add_klingelnberg_options(cmd, flags);
}

void add_measured_against_option(CLI::App* cmd, KlingelnbergFlags& flags) {
  add_word_option<measurement::MeasuredAgainst>(
      cmd, "--measured-against", flags.against,
      {{"design", measurement::MeasuredAgainst::design}, {"involute", measurement::MeasuredAgainst::involute}},
      "What a measurement without a design_um column is measured from: design (the scene's drawing, as a measuring "
      "machine that evaluates against it writes) or involute (the bare involute); not given: the bare involute, and "
      "diagnose says when the residual looks like minus the design (docs/modifications.md)",
      nullptr); // for every format: not one of the --mka-… flags refused without an export
}

measurement::MeasuredAgainst measured_against(const workbench::Workbench& wb, const std::string& file,
                                              const KlingelnbergFlags& flags) {
  if (flags.against != measurement::MeasuredAgainst::as_file) return flags.against;
  const auto& grid = wb.scene.grid;
  if (!grid.measured_against.empty() && file == grid.measured_file)
    return measurement::parse_measured_against(grid.measured_against).value_or(measurement::MeasuredAgainst::as_file);
  return measurement::MeasuredAgainst::as_file;
}

void refuse_mka_flags_without_export(const std::string& file, const KlingelnbergFlags& flags) {
  if (flags.given.empty()) return;
  if (file.empty())
    throw CLI::ValidationError(flags.given.front(), "has no effect: no measurement is read (give --measured, or "
                                                    "measurement.measured in the scene)");
  std::ifstream in(file, std::ios::binary); // unreadable: the reader says why
  if (!in || measurement::looks_like_klingelnberg(in)) return;
  throw CLI::ValidationError(flags.given.front(),
                             fmt::format("has no effect: {} is not a Klingelnberg export (the --mka-… options read "
                                         "exports only)",
                                         file));
}

std::vector<measurement::MeasuredPoint> read_measured_points(const workbench::Workbench& wb, const std::string& file,
                                                             const KlingelnbergFlags& flags,
                                                             measurement::ReadCounts* counts) {
  refuse_mka_flags_without_export(file, flags);
  std::vector<std::string> warnings;
  auto points = measurement::read_any_measurement(file, wb.setup, &warnings, flags.options, counts,
                                                  measured_against(wb, file, flags));
  for (const auto& w : warnings) say("geartopo: warning: " + w);
  return points;
}

} // namespace geartopo::app
