#include "app/report_command.hpp"

#include "app/commands.hpp"
#include "app/messages.hpp"
#include "app/pipeline_job.hpp"
#include "app/series_command.hpp"

#include "geartopo/series/series_file.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>

namespace geartopo::app {

int run_report(const ReportOptions& opt) {
  if (series::is_series_file(opt.scene)) {
    if (!opt.other_flags_given.empty())
      throw CLI::ValidationError(opt.other_flags_given.front(),
                                 fmt::format("has no effect: {} is a series file, whose gears name their measurements "
                                             "and whose spec the rest (docs/series.md); give SCENE and --out only",
                                             opt.scene));
    return run_series_report(opt.scene, opt.out);
  }
  const output::RunFiles files = report_files(opt.scene, opt.measured);
  output::check_run_files(opt.out, files); // before any work: no input and no user's file is replaced
  const Workbench wb(opt.scene);
  const std::filesystem::path dir(opt.out);
  output::OutputFolder folder(dir, files);
  pipeline::PipelineOptions po;
  set_measurement(po, wb, opt.measured, opt.mka);
  po.iso = opt.iso;
  po.prediction = prediction_options(opt.mc);
  const ReportJob job = run_report_job(wb, po, opt.scene, dir, opt.mc.max_time_s);
  std::cout << fmt::format("wrote {} figures and {}\n", job.figures.size(), (dir / "index.html").string());
  finish_output_folder(folder);
  return 0;
}

} // namespace geartopo::app
