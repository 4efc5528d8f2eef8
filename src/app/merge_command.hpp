// geartopo merge PARTS... --out DIR: the Monte Carlo shards' samples combined into the prediction one run writes,
// bit for bit (docs/monte-carlo.md).
#pragma once

#include <string>
#include <vector>

namespace geartopo::app {

struct MergeOptions {
  std::vector<std::string> parts; ///< prediction_samples.csv of each shard
  std::string out;
};

/// The command's work once its flags are parsed (merge_command.cpp); returns the exit code.
int run_merge(const MergeOptions& opt);

} // namespace geartopo::app
