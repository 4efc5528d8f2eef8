#include "app/series_command.hpp"

#include "app/messages.hpp"

#include "geartopo/aqdef/aqdef.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/output_folder.hpp"
#include "geartopo/report/series_report.hpp"
#include "geartopo/series/aqdef_export.hpp"
#include "geartopo/series/run_charts.hpp"
#include "geartopo/series/series_analysis.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>

namespace geartopo::app {

namespace {

/// A scene text written as AQDEF `key`, refused at its scene field when the key cannot hold it (aqdef::text_refusal).
std::string scene_text(const Workbench& wb, const std::string& field, const std::string& text, const char* key) {
  if (const auto why = aqdef::text_refusal(key, text)) wb.scene.fail_at(field, fmt::format("{} (written by --aqdef)", *why));
  return text;
}

/// K1001: the drawing's number; without one, the first of the part's description, the scene's name and its file's
/// stem that K1001 holds (30 characters: a description is often longer). None: refused at report.drawing.
std::string part_number(const Workbench& wb) {
  const auto& r = wb.scene.report;
  if (!r.drawing.empty()) return scene_text(wb, "report.drawing", r.drawing, "K1001");
  const std::string stem = std::filesystem::path(wb.scene.source).stem().string();
  for (const std::string* candidate : {&r.part, &wb.scene.name, &stem})
    if (!candidate->empty() && !aqdef::text_refusal("K1001", *candidate)) return *candidate;
  wb.scene.fail_at("report.drawing", fmt::format("none given, and neither report.part, the scene's name nor its file "
                                                 "name fits the {} characters of AQDEF K1001 (the part number), "
                                                 "written by --aqdef",
                                                 aqdef::max_characters("K1001")));
}

} // namespace

series::AqdefHeader aqdef_header(const Workbench& wb, const std::string& batch, const std::string& machine) {
  const auto& r = wb.scene.report;
  series::AqdefHeader h;
  h.part_number = part_number(wb);
  h.part_description = !r.part.empty() ? scene_text(wb, "report.part", r.part, "K1002")
                                       : scene_text(wb, "name", wb.scene.name, "K1002");
  // The series file's machine is checked where it is read; the scene's machine.name is often a description longer
  // than K1082 holds (the default scene's: 72 characters): then no K1082 rather than a cut one.
  h.machine = !machine.empty()                                            ? machine
              : aqdef::text_refusal("K1082", wb.scene.machine.name) ? std::string()
                                                                        : wb.scene.machine.name;
  h.batch = batch; // the series file's name, checked where it is read (series_file.cpp)
  return h;
}

namespace {

/// The series analysed and its files written into `out`: series.json, the run charts, the closed-loop figure.
struct SeriesRun {
  series::SeriesResult result; ///< its spec is the series file read
  report::SeriesFigures figures;
};

SeriesRun analyse_and_write(const std::string& series_file, const Workbench& wb, const std::filesystem::path& out) {
  SeriesRun run;
  run.result = series::analyse_series(series::load_series(series_file, series::strokes_per_gear(wb)), wb);
  output::write_text_atomically(out / "series.json", series::series_json(run.result).dump(2) + "\n");
  run.figures.run_charts = series::write_run_charts(run.result, out);
  run.figures.closed_loop = series::write_closed_loop_figure(run.result, out);
  std::cout << series::series_text(run.result);
  return run;
}

void write_aqdef(const std::string& file, const std::string& series_file, const Workbench& wb, const SeriesRun& run) {
  std::vector<series::AqdefGear> gears;
  for (const auto& g : run.result.gears)
    if (g.iso) gears.push_back({&g.iso->evaluation, g.gear.start_epoch_s, g.gear.id});
  if (gears.empty()) say(fmt::format("geartopo: warning: no gear of {} holds traces: {} holds no values", series_file, file));
  const auto params = workbench::gear_parameters(wb.setup.geometry());
  aqdef::write_dfq(file, series::iso_aqdef(gears, params, run.result.drawing_class,
                                           aqdef_header(wb, run.result.spec.name, run.result.spec.machine)));
  std::cout << "wrote " << file << "\n";
}

} // namespace

int run_series(const SeriesOptions& opt) {
  const std::filesystem::path scene = series::series_scene(opt.series);
  const output::RunFiles files{{opt.series, scene}, {"series.json"}};
  output::OutputFolder folder(opt.out, files);
  const Workbench wb(scene);
  const std::filesystem::path out(opt.out);
  const SeriesRun run = analyse_and_write(opt.series, wb, out);
  if (!opt.aqdef.empty()) write_aqdef(opt.aqdef, opt.series, wb, run);
  std::cout << "wrote " << (out / "series.json").string() << " and " << run.figures.run_charts.size() << " run charts"
            << (run.figures.closed_loop ? " and " + run.figures.closed_loop->filename().string() + " (synthetic)" : std::string())
            << "\n";
  finish_output_folder(folder);
  return 0;
}

int run_series_report(const std::string& series_file, const std::string& out_dir) {
  const std::filesystem::path scene = series::series_scene(series_file);
  const output::RunFiles files{{series_file, scene}, {"series.json", "index.html"}};
  output::OutputFolder folder(out_dir, files);
  const Workbench wb(scene);
  const std::filesystem::path out(out_dir);
  const SeriesRun run = analyse_and_write(series_file, wb, out);
  report::write_series_report(out, wb, run.result, run.figures);
  std::cout << "wrote " << (out / "index.html").string() << ", series.json and " << run.figures.run_charts.size()
            << " run charts\n";
  finish_output_folder(folder);
  return 0;
}

} // namespace geartopo::app
