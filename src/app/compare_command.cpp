// geartopo compare: measured − model, where the model fails, and the residual's patterns.
#include "app/commands.hpp"
#include "geartopo/core/atomic_file.hpp"
#include "app/options.hpp"

#include "geartopo/diagnosis/compare.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

namespace geartopo::app {
namespace {

nlohmann::json estimate_json(const diagnosis::Estimate& e) { return {{"value", e.value}, {"standard_error", e.standard_error}}; }

nlohmann::json stats_json(const diagnosis::ResidualStats& s) {
  return {{"points", s.points}, {"rms_um", s.rms_um}, {"max_abs_um", s.max_abs_um}, {"extreme_um", s.extreme_um}};
}

nlohmann::json wave_json(const diagnosis::WavinessScan& w) {
  if (!w.wave) return nullptr;
  return {{"amplitude_um", estimate_json(w.wave->amplitude_um)}, {"wavelength_mm", w.wave->wavelength_mm},
          {"first_crest_mm", w.wave->first_crest_mm}};
}

} // namespace

void register_compare_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, measured, out;
    double noise = 0.0;
    diagnosis::KlingelnbergOptions mka;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("compare", "Measured − model (µm) at every measured point: statistics, where the model "
                                                "fails, and the residual's patterns");
  cmd->add_option("SCENE", opt->scene, "Model scene (YAML)")->required();
  cmd->add_option("--measured", opt->measured, "Measurement: topology CSV (µm), traces CSV, point cloud x_mm,y_mm,z_mm, or Klingelnberg export "
                                                   "(docs/measurement-formats.md); told apart by content")->required();
  cmd->add_option("--out", opt->out, "Output directory: compare.json, residuals.csv")->required()->check(non_empty_path());
  cmd->add_option("--noise-um", opt->noise, "Probe noise σ in µm (default: estimated)")->check(finite_in(0.0, 1000.0));
  add_klingelnberg_options(cmd, opt->mka);
  cmd->callback([&action, opt] {
    action = [opt] {
      const Workbench wb(opt->scene);
      std::vector<std::string> warnings;
      const auto pts = diagnosis::read_any_measurement(opt->measured, wb.setup, &warnings, opt->mka);
      for (const auto& w : warnings) std::cerr << "geartopo: warning: " << w << "\n";
      const auto c = diagnosis::compare(wb.setup, wb.process(), pts, opt->noise);

      const std::filesystem::path out(opt->out);
      output::OutputFolder folder(out);
      output::write_atomically(out / "residuals.csv", [&](std::ostream& csv) {
        csv << "tooth,flank,row,col,diameter_mm,z_mm,measured_um,model_um,residual_um\n";
        for (size_t i = 0; i < pts.size(); ++i)
          csv << fmt::format("{},{},{},{},{:.6f},{:.6f},{:.4f},{:.4f},{:.4f}\n", pts[i].tooth, gears::to_string(pts[i].flank),
                             pts[i].row, pts[i].col, pts[i].diameter_mm, pts[i].z_mm, pts[i].deviation_um, c.model_um[i],
                             c.residual_um[i]);
      });
      nlohmann::json j;
      j["scene"] = opt->scene;
      j["measured"] = opt->measured;
      j["units"] = "µm; residual = measured − model, along the flank normal, plus material positive; the model's nominal "
                   "flank is at the mean tooth-thickness allowance";
      j["nominal_offset_at_mean_allowance_um"] = c.allowance_offset_um;
      j["points_without_grid_indices"] = std::count_if(pts.begin(), pts.end(), [](const auto& p) { return p.row == 0; });
      j["noise_um"] = c.noise_um;
      j["noise_estimated"] = c.noise_estimated;
      j["overall"] = stats_json(c.summary.overall);
      nlohmann::json flanks = nlohmann::json::array();
      for (size_t f = 0; f < c.flanks.size(); ++f) {
        nlohmann::json fj;
        fj["tooth"] = c.flanks[f].tooth;
        fj["flank"] = diagnosis::to_string(c.flanks[f].side);
        fj["stats"] = stats_json(c.summary.flanks[f].stats);
        if (c.has_patterns[f]) {
          const auto& p = c.patterns[f];
          fj["patterns"] = {{"offset_um", estimate_json(p.offset_um)},
                            {"profile_slope_um", estimate_json(p.profile_slope_um)},
                            {"helix_slope_um", estimate_json(p.helix_slope_um)},
                            {"twist_um", estimate_json(p.twist_um)},
                            {"profile_crowning_um", estimate_json(p.profile_crowning_um)},
                            {"helix_crowning_um", estimate_json(p.helix_crowning_um)},
                            {"waviness_along_profile", wave_json(p.waviness_profile)},
                            {"waviness_along_helix", wave_json(p.waviness_helix)},
                            {"rms_unexplained_um", p.rms_unexplained_um}};
          fj["description"] = diagnosis::describe_patterns(p);
        }
        flanks.push_back(fj);
      }
      j["flanks"] = flanks;
      nlohmann::json teeth = nlohmann::json::array();
      for (const auto& t : c.summary.teeth) teeth.push_back({{"tooth", t.tooth}, {"stats", stats_json(t.stats)}});
      j["teeth"] = teeth;
      nlohmann::json trends = nlohmann::json::array();
      for (const auto& s : c.trends)
        for (const auto& t : s.trends) trends.push_back({{"flank", diagnosis::to_string(s.side)}, {"sentence", t.sentence}});
      j["tooth_to_tooth"] = trends;
      nlohmann::json regions = nlohmann::json::array();
      for (const auto& r : c.regions) regions.push_back(r.sentence);
      j["failing_regions"] = regions;
      output::write_text_atomically(out / "compare.json", j.dump(2) + "\n");

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
      std::cout << "wrote " << (out / "compare.json").string() << ", residuals.csv\n";
      finish_output_folder(folder);
      return 0;
    };
  });
}

} // namespace geartopo::app
