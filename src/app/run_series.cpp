#include "app/series_command.hpp"

#include "app/messages.hpp"

#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/output_folder.hpp"
#include "geartopo/series/aqdef_export.hpp"
#include "geartopo/series/run_charts.hpp"
#include "geartopo/series/series_analysis.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>

namespace geartopo::app {

series::AqdefHeader aqdef_header(const Workbench& wb, const std::string& batch, const std::string& machine) {
  const auto& r = wb.scene.report;
  series::AqdefHeader h;
  h.part_number = !r.drawing.empty() ? r.drawing : !r.part.empty() ? r.part : wb.scene.name;
  h.part_description = !r.part.empty() ? r.part : wb.scene.name;
  h.machine = !machine.empty() ? machine : wb.scene.machine.name;
  h.batch = batch;
  return h;
}

int run_series(const SeriesOptions& opt) {
  const std::filesystem::path scene = series::series_scene(opt.series);
  const output::RunFiles files{{opt.series, scene}, {"series.json"}};
  output::OutputFolder folder(opt.out, files);
  const Workbench wb(scene);
  const auto spec = series::load_series(opt.series, series::strokes_per_gear(wb));
  const auto result = series::analyse_series(spec, wb);
  const std::filesystem::path out(opt.out);
  output::write_text_atomically(out / "series.json", series::series_json(result).dump(2) + "\n");
  const auto charts = series::write_run_charts(result, out);
  std::cout << series::series_text(result);
  if (!opt.aqdef.empty()) {
    std::vector<series::AqdefGear> gears;
    for (const auto& g : result.gears)
      if (g.iso) gears.push_back({&g.iso->evaluation, g.gear.start_epoch_s, g.gear.id});
    if (gears.empty())
      say(fmt::format("geartopo: warning: no gear of {} holds traces: {} holds no values", opt.series, opt.aqdef));
    const auto params = workbench::gear_parameters(wb.setup.geometry());
    aqdef::write_dfq(opt.aqdef, series::iso_aqdef(gears, params, result.drawing_class, aqdef_header(wb, spec.name, spec.machine)));
    std::cout << "wrote " << opt.aqdef << "\n";
  }
  std::cout << "wrote " << (out / "series.json").string() << " and " << charts.size() << " run charts\n";
  finish_output_folder(folder);
  return 0;
}

} // namespace geartopo::app
