#include "app/merge_command.hpp"

#include "app/commands.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_merge_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<MergeOptions>();
  CLI::App* cmd = app.add_subcommand("merge", "Combine the Monte Carlo shards' prediction_samples.csv into one prediction "
                                              "(prediction.json, prediction.txt, prediction_samples.csv)");
  cmd->add_option("PARTS", opt->parts, "Partial results (prediction_samples.csv of each shard)")->required();
  cmd->add_option("--out", opt->out, "Output directory (created)")->required()->check(non_empty_path());
  cmd->callback([&action, opt] { action = [opt] { return run_merge(*opt); }; });
}

} // namespace geartopo::app
