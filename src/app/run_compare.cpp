// geartopo compare's work (measured_commands.hpp): compare.json, residuals.csv, the residual against the process.
#include "app/json_summary.hpp"
#include "app/messages.hpp"
#include "app/run_measured.hpp"

#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/output_folder.hpp"
#include "geartopo/report/measurement_report.hpp"
#include "geartopo/report/residual_follows_figure.hpp"

#include <filesystem>
#include <iostream>

namespace geartopo::app {

int run_compare(const CompareFlags& opt) {
  JsonSummary json(opt.json);
  const output::RunFiles files{{opt.scene, opt.measured}, {"residuals.csv", "compare.json"}};
  output::OutputFolder folder(opt.out, files); // locked and staged before any work: a second run is refused now
  const LoadedScene scene = load_scene_for(opt);
  measurement::ReadCounts read;
  const auto pts = read_measured_points(*scene.wb, opt.measured, opt.mka, &read);
  const auto r = commands::compare(scene.input(), {pts, opt.measured, read}, opt.noise, cli_argument_names());
  const auto& c = r.comparison;

  const std::filesystem::path out(opt.out);
  report::write_residuals_csv(out / "residuals.csv", pts, c);
  output::write_text_atomically(out / "compare.json", r.json.dump(2) + "\n");
  std::cout << report::compare_summary_text(c);
  if (!c.follows.variables.empty())
    report::render_residual_follows(c.follows, pts, out / "residual_vs_process.png", out / "panels");
  std::cout << "wrote " << (out / "compare.json").string() << ", residuals.csv"
            << (c.follows.variables.empty() ? "" : ", residual_vs_process.png") << "\n";
  finish_output_folder(folder);
  json.emit(r.json);
  return 0;
}

} // namespace geartopo::app
