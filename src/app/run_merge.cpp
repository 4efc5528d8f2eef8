#include "app/merge_command.hpp"

#include "app/messages.hpp"
#include "app/monte_carlo_flags.hpp"

#include "geartopo/files/output_folder.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/report/prediction_report.hpp"

#include <filesystem>
#include <iostream>

namespace geartopo::app {

int run_merge(const MergeOptions& opt) {
  const output::RunFiles files{{opt.parts.begin(), opt.parts.end()},
                               {"prediction_samples.csv", "prediction.json", "prediction.txt"}};
  output::OutputFolder folder(opt.out, files); // locked and staged before any work: a second run is refused now
  std::vector<pipeline::MonteCarloRun> runs;
  for (const auto& p : opt.parts) runs.push_back(pipeline::read_run_csv(p));
  const auto merged = pipeline::merge_runs(std::move(runs));
  const auto summary = pipeline::summarise(merged);
  const std::filesystem::path out(opt.out);
  pipeline::write_run_csv(out / "prediction_samples.csv", merged);
  write_prediction(out, summary);
  for (const auto& l : report::prediction_lines(summary)) std::cout << l << "\n";
  std::cout << "wrote " << out.string() << "/prediction.json, prediction.txt, prediction_samples.csv\n";
  finish_output_folder(folder);
  return 0;
}

} // namespace geartopo::app
