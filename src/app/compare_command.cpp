// geartopo compare: measured − model, where the model fails, and the residual's patterns.
#include "app/commands.hpp"
#include "geartopo/core/atomic_file.hpp"
#include "app/options.hpp"

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
    measurement::KlingelnbergOptions mka;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("compare", "Measured − model (µm) at every measured point: statistics, where the model "
                                                "fails, and the residual's patterns");
  cmd->add_option("SCENE", opt->scene, "Model scene (YAML)")->required();
  add_measurement_options(cmd, opt->measured, opt->mka);
  cmd->add_option("--out", opt->out, "Output directory: compare.json, residuals.csv")->required()->check(non_empty_path());
  cmd->add_option("--noise-um", opt->noise, "Probe noise σ in µm (default: estimated)")->check(finite_in(0.0, 1000.0));
  cmd->add_flag("--json", opt->json, "Print compare.json's content on stdout instead of the text summary");
  cmd->callback([&action, opt] {
    action = [opt] {
      JsonSummary json(opt->json);
      const Workbench wb(opt->scene);
      const auto pts = read_measured_points(wb, opt->measured, opt->mka);
      const auto c = diagnosis::compare(wb.setup, wb.process(), pts, opt->noise);

      const std::filesystem::path out(opt->out);
      output::OutputFolder folder(out);
      report::write_residuals_csv(out / "residuals.csv", pts, c);
      const nlohmann::json summary = report::compare_json(opt->scene, opt->measured, pts, c);
      output::write_text_atomically(out / "compare.json", summary.dump(2) + "\n");

      std::cout << fmt::format("{} measured points on {} flanks; residual (measured − model) {:.2f} µm RMS, max |{:.2f}| µm; "
                               "noise {:.2f} µm{}\n",
                               pts.size(), c.flanks.size(), c.summary.overall.rms_um, c.summary.overall.max_abs_um, c.noise_um,
                               c.noise_estimated ? " (estimated)" : "");
      std::cout << fmt::format("Model: nominal flank at mean allowance {:+.2f} µm (along the normal, every flank)\n",
                               c.allowance_offset_um);
      for (size_t f = 0; f < c.flanks.size(); ++f)
        std::cout << fmt::format("  tooth {:>3} {:<5}  RMS {:6.2f} µm  max {:6.2f} µm\n", c.flanks[f].tooth,
                                 diagnosis::to_string(c.flanks[f].side), c.summary.flanks[f].stats.rms_um,
                                 c.summary.flanks[f].stats.max_abs_um);
      if (c.regions.empty())
        std::cout << "Where the model fails: nowhere above 3σ of the noise.\n";
      else {
        std::cout << "Where the model fails (|residual| > 3σ):\n";
        for (const auto& r : c.regions) std::cout << "  " << r.sentence << "\n";
      }
      std::cout << "Patterns of the residual:\n";
      for (size_t f = 0; f < c.flanks.size(); ++f)
        if (c.has_patterns[f]) std::cout << "  " << diagnosis::describe_patterns(c.patterns[f]) << "\n";
      for (const auto& s : c.trends)
        for (const auto& t : s.trends)
          if (!t.sentence.empty()) std::cout << "  " << t.sentence << "\n";
      if (!c.follows.variables.empty()) {
        std::cout << "What the residual follows (each process variable alone, set-up terms removed; strongest first):\n";
        for (const auto& d : c.follows.variables)
          std::cout << "  " << d.sentence << (d.significant ? "" : " — not significant") << "\n";
        report::render_residual_follows(c.follows, pts, out / "residual_vs_process.png", out / "panels");
      }
      std::cout << "wrote " << (out / "compare.json").string() << ", residuals.csv"
                << (c.follows.variables.empty() ? "" : ", residual_vs_process.png") << "\n";
      finish_output_folder(folder);
      json.emit(summary);
      return 0;
    };
  });
}

} // namespace geartopo::app
