// geartopo compare: measured − model, where the model fails, and the residual's patterns.
#include "app/commands.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "app/json_summary.hpp"
#include "app/measurement_options.hpp"
#include "app/messages.hpp"
#include "app/validators.hpp"
#include "geartopo/files/output_folder.hpp"

#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/report/residual_follows_figure.hpp"
#include "geartopo/report/measurement_report.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

namespace geartopo::app {

void register_compare_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, measured, out;
    double noise = 0.0;
    bool json = false;
    KlingelnbergFlags mka;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("compare", "Measured − model (µm) at every measured point: statistics, where the model "
                                                "fails, and the residual's patterns");
  cmd->add_option("SCENE", opt->scene, "Model scene (YAML)")->required();
  add_measurement_options(cmd, opt->measured, opt->mka);
  cmd->add_option("--out", opt->out, "Output directory: compare.json, residuals.csv")->required()->check(non_empty_path());
  cmd->add_option("--noise-um", opt->noise, "Probe noise σ in µm (default: estimated)")->check(probe_sigma_um());
  cmd->add_flag("--json", opt->json, "Print compare.json's content on stdout instead of the text summary");
  cmd->callback([&action, opt] {
    action = [opt] {
      JsonSummary json(opt->json);
      const output::RunFiles files{{opt->scene, opt->measured}, {"residuals.csv", "compare.json"}};
      output::OutputFolder folder(opt->out, files); // locked and staged before any work: a second run is refused now
      const Workbench wb(opt->scene);
      measurement::ReadCounts read;
      const auto pts = read_measured_points(wb, opt->measured, opt->mka, &read);
      const auto c = diagnosis::compare(wb.setup, wb.process(), pts, opt->noise, read);

      const std::filesystem::path out(opt->out);
      report::write_residuals_csv(out / "residuals.csv", pts, c);
      const nlohmann::json summary = report::compare_json(opt->scene, opt->measured, pts, c);
      output::write_text_atomically(out / "compare.json", summary.dump(2) + "\n");

      std::cout << report::compare_summary_text(c);
      if (!c.follows.variables.empty())
        report::render_residual_follows(c.follows, pts, out / "residual_vs_process.png", out / "panels");
      std::cout << "wrote " << (out / "compare.json").string() << ", residuals.csv"
                << (c.follows.variables.empty() ? "" : ", residual_vs_process.png") << "\n";
      finish_output_folder(folder);
      json.emit(summary);
      return 0;
    };
  });
}

} // namespace geartopo::app
