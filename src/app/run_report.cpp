#include "app/report_command.hpp"

#include "app/commands.hpp"
#include "app/messages.hpp"
#include "app/pipeline_job.hpp"
#include "app/series_command.hpp"

#include "geartopo/report/html_report.hpp"
#include "geartopo/series/series_file.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>

namespace geartopo::app {

int run_report(const ReportOptions& opt) {
  if (series::is_series_file(opt.scene)) {
    if (!opt.measured.empty())
      throw CLI::ValidationError("--measured", fmt::format("has no effect: {} is a series file, whose gears name their "
                                                           "measurements", opt.scene));
    return run_series_report(opt.scene, opt.out);
  }
  const output::RunFiles files = report_files(opt.scene, opt.measured);
  output::check_run_files(opt.out, files); // before any work: no input and no user's file is replaced
  const Workbench wb(opt.scene);
  const std::filesystem::path dir(opt.out);
  output::OutputFolder folder(dir, files);
  pipeline::PipelineOptions po;
  po.measured_file = measured_of(wb, opt.measured);
  refuse_mka_flags_without_export(po.measured_file, opt.mka);
  po.measurement_format = opt.mka.options;
  po.measured_against = measured_against(wb, po.measured_file, opt.mka);
  po.iso = opt.iso;
  po.prediction = prediction_options(opt.mc);
  print_pipeline_estimate(wb, po);
  StageProgress progress(po, opt.mc.max_time_s);
  BeforeFigures before(po, wb, dir);
  const auto r = pipeline::run_pipeline(wb, po);
  progress.finish();
  if (r.measurement)
    for (const auto& w : r.measurement->warnings) say("geartopo: warning: " + w);
  write_data_files(dir, opt.scene, wb, r); // the page names them (corrections.csv, scene_with_effect.yaml …)
  const auto figs = report::write_report(dir, wb, r, {}, before.take());
  std::cout << fmt::format("wrote {} figures and {}\n", figs.size(), (dir / "index.html").string());
  finish_output_folder(folder);
  return 0;
}

} // namespace geartopo::app
