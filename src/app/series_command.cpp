#include "app/series_command.hpp"

#include "app/commands.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_series_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<SeriesOptions>();
  CLI::App* cmd = app.add_subcommand("series", "A production series of measured gears: per gear its ISO 1328-1 values "
                                               "and residual, the drift across the gears (thermal drift, wheel wear and "
                                               "re-dress, correction steps) with σ, the next gear predicted and when the "
                                               "drawing's class is expected to be lost (docs/series.md)");
  cmd->add_option("SERIES", opt->series, "Series file (YAML, docs/scene-format.md \"Series files\")")->required();
  cmd->add_option("--out", opt->out, "Output directory (created): series.json, run_chart_<quantity>.png")
      ->required()
      ->check(non_empty_path());
  cmd->add_option("--aqdef", opt->aqdef, "Also write the gears' ISO 1328-1 values per tooth and flank as an AQDEF file "
                                         "(.dfq, docs/aqdef.md) for the quality system")
      ->check(non_empty_path());
  cmd->callback([&action, opt] { action = [opt] { return run_series(*opt); }; });
}

} // namespace geartopo::app
