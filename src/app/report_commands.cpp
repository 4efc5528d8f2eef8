// geartopo report / run: the report, and the main job (everything, with a short summary).
#include "app/commands.hpp"
#include "geartopo/core/atomic_file.hpp"
#include "geartopo/report/html_report.hpp"
#include "geartopo/report/iso_report.hpp"
#include "geartopo/pipeline/pipeline.hpp"
#include "app/options.hpp"
#include "app/monte_carlo_flags.hpp"
#include "geartopo/report/prediction_report.hpp"

#include "geartopo/diagnosis/scene_writer.hpp"
#include "geartopo/grinding/topology_csv.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

namespace geartopo::app {
namespace {

namespace fs = std::filesystem;

std::string measured_of(const Workbench& wb, const std::string& option) {
  return option.empty() ? wb.scene.grid.measured_file : option;
}

void write_data_files(const fs::path& dir, const std::string& scene_file, const Workbench& wb, const pipeline::PipelineResult& r) {
  grinding::write_topology_csv(dir / "topology_before.csv", r.before);
  grinding::write_topology_csv(dir / "topology_after.csv", r.after);
  grinding::write_traces_csv(dir / "traces_before.csv", r.before);
  grinding::write_traces_csv(dir / "traces_after.csv", r.after);
  r.corrections->write_csv(dir / "corrections.csv");
  nlohmann::json iso;
  iso["scene"] = wb.scene.name;
  iso["units"] = "µm; deviations along the flank normal, plus material positive";
  iso["before"] = report::iso_json(r.iso_before);
  iso["after"] = report::iso_json(r.iso_after);
  iso["warnings"] = nlohmann::json::array();
  const std::string worse = compensation_made_worse(grinding::largest_abs_deviation_um(r.before),
                                                    grinding::largest_abs_deviation_um(r.after));
  if (!worse.empty()) {
    std::cerr << "geartopo: warning: " << worse << "\n";
    iso["warnings"].push_back(worse);
  }
  if (r.prediction) {
    iso["prediction"] = report::prediction_json(*r.prediction);
    write_prediction(dir, *r.prediction);
  }
  output::write_text_atomically(dir / "iso1328.json", iso.dump(2) + "\n");
  if (r.measurement && r.measurement->diagnosis.chosen) {
    std::vector<std::string> comments;
    for (const auto& e : r.measurement->diagnosis.chosen->effects)
      comments.push_back(e.type + ": identified by geartopo from " + r.measurement->file);
    diagnosis::write_scene_with_effects(scene_file, r.measurement->diagnosis.chosen->effects, comments,
                                        dir / "scene_with_effect.yaml");
  }
}

void print_summary(const fs::path& dir, const pipeline::PipelineResult& r) {
  const auto& cb = r.iso_before.evaluation.classification;
  const auto& ca = r.iso_after.evaluation.classification;
  if (r.prediction) { // the after-state as a band (docs/monte-carlo.md), never the model's own ≈ 0
    for (const auto& l : report::prediction_lines(*r.prediction)) std::cout << l << "\n";
  } else {
    std::cout << fmt::format("Largest |deviation| ({} grids, all teeth): {:.2f} µm before; the nominal model compensating "
                             "itself: {:.2f} µm (no prediction: --samples 0)\n",
                             pipeline::grid_label(r), r.largest_before_um, r.largest_after_um);
    std::cout << fmt::format("ISO 1328-1 overall flank tolerance class: {} before, {} nominal after{}\n", evaluation::class_label(cb.overall), evaluation::class_label(ca.overall),
                             cb.governing ? fmt::format(" (before: set by {})", evaluation::symbol(*cb.governing)) : "");
  }
  if (r.measurement) {
    const auto& m = *r.measurement;
    std::cout << fmt::format("Measurement {}: residual {:.2f} µm RMS against the model\n", m.file, m.before.summary.overall.rms_um);
    if (!m.diagnosis.ranked.empty())
      std::cout << fmt::format("Top diagnosis: {} (ΔBIC {:.1f}, explains {:.0f} %)\n", m.diagnosis.ranked.front().name(),
                               m.diagnosis.ranked.front().delta_bic, 100 * m.diagnosis.ranked.front().explained_fraction);
    std::cout << m.diagnosis.verdict << "\n";
  }
  std::cout << "Report: " << (dir / "index.html").string() << "\n";
}

} // namespace

void register_report_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, measured, out;
    MonteCarloFlags mc;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("report", "Figures (PNG, rendered off-screen) and an offline index.html: topology, "
                                               "traces, pitch, machine errors, before/after, measured vs model, diagnosis");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML)")->required();
  cmd->add_option("--measured", opt->measured, "Measurement (topology CSV or point cloud); default: the scene's measurement.measured");
  cmd->add_option("--out", opt->out, "Output directory")->required()->check(non_empty_path());
  add_monte_carlo_options(cmd, opt->mc, false);
  cmd->callback([&action, opt] {
    action = [opt] {
      const Workbench wb(opt->scene);
      const fs::path dir(opt->out);
      fs::create_directories(dir);
      const auto r = pipeline::run_pipeline(wb, measured_of(wb, opt->measured), prediction_options(opt->mc));
      write_data_files(dir, opt->scene, wb, r); // the page names them (corrections.csv, scene_with_effect.yaml …)
      const auto figs = report::write_report(dir, wb, r);
      std::cout << fmt::format("wrote {} figures and {}\n", figs.size(), (dir / "index.html").string());
      return 0;
    };
  });
}

void register_run_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, out;
    MonteCarloFlags mc;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("run", "The main job: simulate, evaluate (ISO 1328-1), compensate, compare and diagnose "
                                            "when the scene names a measurement, and write the report");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML)")->required();
  cmd->add_option("--out", opt->out, "Output directory")->required()->check(non_empty_path());
  add_monte_carlo_options(cmd, opt->mc, false);
  cmd->callback([&action, opt] {
    action = [opt] {
      const Workbench wb(opt->scene);
      const fs::path dir(opt->out);
      fs::create_directories(dir);
      std::cout << "geartopo run: " << (wb.scene.name.empty() ? opt->scene : wb.scene.name) << "\n";
      const auto r = pipeline::run_pipeline(wb, wb.scene.grid.measured_file, prediction_options(opt->mc));
      write_data_files(dir, opt->scene, wb, r);
      report::write_report(dir, wb, r);
      print_summary(dir, r);
      return 0;
    };
  });
}

} // namespace geartopo::app
