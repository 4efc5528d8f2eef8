// geartopo report / run: the report, and the main job (everything, with a short summary).
#include "app/commands.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/report/figures.hpp"
#include "geartopo/report/html_report.hpp"
#include "geartopo/report/iso_report.hpp"
#include "geartopo/report/measurement_report.hpp"
#include "geartopo/pipeline/pipeline.hpp"
#include "app/options.hpp"
#include "app/monte_carlo_flags.hpp"
#include "geartopo/report/prediction_report.hpp"
#include "geartopo/report/improvement.hpp"

#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/diagnosis/scene_writer.hpp"
#include "geartopo/grinding/topology_csv.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <future>
#include <fstream>
#include <iostream>
#include <memory>

namespace geartopo::app {
namespace {

namespace fs = std::filesystem;

std::string measured_of(const Workbench& wb, const std::string& option) {
  return option.empty() ? wb.scene.grid.measured_file : option;
}

/// What `report` and `run` read and always write (the figures and the files of a measurement are checked as they are
/// written).
output::RunFiles report_files(const std::string& scene, const std::string& measured) {
  return {{scene, measured},
          {"index.html", "iso1328.json", "corrections.csv", "topology_before.csv", "topology_after.csv",
           "traces_before.csv", "traces_after.csv"}};
}

/// Writes the data files and returns iso1328.json's content (run --json prints it with the measurement's verdict).
nlohmann::json write_data_files(const fs::path& dir, const std::string& scene_file, const Workbench& wb, const pipeline::PipelineResult& r) {
  grinding::write_topology_csv(dir / "topology_before.csv", r.before);
  grinding::write_topology_csv(dir / "topology_after.csv", r.after);
  grinding::write_traces_csv(dir / "traces_before.csv", r.before);
  grinding::write_traces_csv(dir / "traces_after.csv", r.after);
  r.corrections->write_csv(dir / "corrections.csv");
  nlohmann::json iso;
  iso["scene"] = wb.scene.name;
  iso["units"] = "µm; plus material positive; profile/helix values in the direction each section names (iso_direction)";
  iso["before"] = report::iso_json(r.iso_before);
  // The model corrected by itself (≈ 0 by construction), under a name that says so; the result is `prediction`.
  iso["nominal_after"] = report::iso_json(r.iso_after);
  iso["nominal_after_meaning"] = report::kNominalAfterMeaning;
  iso["largest_abs_deviation_um"] = {{"before", r.largest_before_um}, {"nominal_after", r.largest_after_um}};
  iso["warnings"] = nlohmann::json::array();
  const std::string worse = compensation_made_worse(grinding::largest_abs_deviation_um(r.before),
                                                    grinding::largest_abs_deviation_um(r.after));
  if (!worse.empty()) {
    say("geartopo: warning: " + worse);
    iso["warnings"].push_back(worse);
  }
  if (r.prediction) {
    iso["prediction"] = report::prediction_json(*r.prediction);
    iso["improvement"] = report::improvement_json(*r.prediction); // from the medians; none without a prediction
    write_prediction(dir, *r.prediction);
    if (const std::string w = prediction_made_worse(*r.prediction); !w.empty()) {
      say("geartopo: warning: " + w);
      iso["warnings"].push_back(w);
    }
  }
  output::write_text_atomically(dir / "iso1328.json", iso.dump(2) + "\n");
  if (r.measurement) { // what `compare` and `diagnose` write, from the same computations (README, "Outputs")
    const auto& m = *r.measurement;
    report::write_residuals_csv(dir / "residuals.csv", m.points, m.before);
    output::write_text_atomically(dir / "compare.json", report::compare_json(scene_file, m.file, m.points, m.before).dump(2) + "\n");
    output::write_text_atomically(
        dir / "diagnosis.json",
        report::diagnosis_json(scene_file, m.file, m.diagnosis, diagnosis::mean_allowance_offset_um(wb.setup.geometry())).dump(2) + "\n");
  }
  // Only an accepted explanation is added (docs/diagnosis.md: not ambiguous, no value at the end of its range).
  if (r.measurement && r.measurement->diagnosis.chosen && r.measurement->diagnosis.withheld.empty()) {
    std::vector<std::string> comments;
    for (const auto& e : r.measurement->diagnosis.chosen->effects)
      comments.push_back(e.type + ": identified by geartopo from " + r.measurement->file);
    diagnosis::write_scene_with_effects(scene_file, r.measurement->diagnosis.chosen->effects, comments,
                                        dir / "scene_with_effect.yaml");
  }
  return iso;
}

/// Draws the report's figures of the gear before compensation on another thread as soon as the pipeline has them
/// (PipelineOptions::before_ready), so that they render while the pipeline compensates, predicts and diagnoses: both
/// cores busy. Installs its callback into `po`, which must not outlive it; take() waits for the figures (and rethrows
/// what drawing them threw).
class BeforeFigures {
public:
  BeforeFigures(pipeline::PipelineOptions& po, const Workbench& wb, fs::path dir) : dir_(std::move(dir)) {
    po.before_ready = [this, &wb, dir = dir_](const pipeline::PipelineResult& r) {
      auto before = std::make_shared<pipeline::PipelineResult>(); // a copy: the pipeline's result moves on
      before->before = r.before;
      before->iso_before = r.iso_before;
      before->largest_before_um = r.largest_before_um;
      figures_ = std::async(std::launch::async, [&wb, dir, before] { return report::render_before_figures(wb, *before, dir); });
    };
  }
  BeforeFigures(const BeforeFigures&) = delete; // the callback holds `this`
  BeforeFigures& operator=(const BeforeFigures&) = delete;
  /// When the job failed after the figures started (e.g. refused by --max-time-s at a later stage): waits for them.
  /// What they wrote is staged (output_folder.hpp) and goes with the failed run's staging folder; the files of that
  /// name in the folder are the earlier run's, which a failed run leaves as they were.
  ~BeforeFigures() {
    if (!figures_.valid()) return; // taken: the report has them
    try {
      figures_.get();
    } catch (...) { // drawing failed too: the job's own error is the one to report
    }
  }
  std::vector<report::Figure> take() { return figures_.valid() ? figures_.get() : std::vector<report::Figure>{}; }

private:
  fs::path dir_;
  std::future<std::vector<report::Figure>> figures_;
};

/// Progress of the pipeline's stages on stderr (a terminal, not --quiet; options.hpp Progress): the flanks of each
/// simulation after its measured work estimate (SimulationWatch), the prediction's samples after theirs
/// (MonteCarloWatch), the diagnosis's candidate fits. The whole job is refused when the time it has spent plus a
/// stage's estimate exceeds max_time_s (--max-time-s). Installs its callbacks into `po`, which must not outlive it.
class StageProgress {
public:
  StageProgress(pipeline::PipelineOptions& po, double max_time_s) {
    po.stage = [this, &po, max_time_s](const std::string& stage, long long size) {
      finish();
      const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - job_start_).count();
      if (stage == pipeline::kPredictionStage)
        watch_ = std::make_unique<MonteCarloWatch>(size, po.prediction ? po.prediction->threads : 0,
                                                   std::max(1e-3, max_time_s - spent),
                                                   "compensate --shard i/n on several machines and geartopo merge",
                                                   po.prediction && po.prediction->adaptive_tolerance_um > 0.0);
      else if (size > 0 && stage.starts_with("simulate"))
        simulation_ = std::make_unique<SimulationWatch>(
            stage, size, 0, max_time_s, job_start_,
            "a coarser grid (measurement.rows/cols) or fewer --teeth, or raise --max-time-s");
      else
        progress_ = std::make_unique<Progress>(stage, size, stage == pipeline::kDiagnoseStage ? "candidate fits" : "flanks");
    };
    po.progress = [this](long long done, long long total) {
      if (simulation_) simulation_->flank_done(done, total);
      else if (progress_) progress_->update(done, total);
    };
    if (po.prediction) {
      po.prediction->on_sample_done = [this](long long done, long long total) {
        if (watch_) watch_->sample_done(done, total);
      };
      po.prediction->on_prepared = [this] {
        if (watch_) watch_->prepared();
      };
    }
  }
  StageProgress(const StageProgress&) = delete; // the callbacks hold `this`
  StageProgress& operator=(const StageProgress&) = delete;
  /// Clears the progress line (before the results are printed).
  void finish() {
    watch_.reset();
    simulation_.reset();
    progress_.reset();
  }

private:
  std::chrono::steady_clock::time_point job_start_ = std::chrono::steady_clock::now();
  std::unique_ptr<Progress> progress_;
  std::unique_ptr<SimulationWatch> simulation_;
  std::unique_ptr<MonteCarloWatch> watch_;
};

/// Before the job: its two simulations (the gear before and after compensation) at the calibrated rate, when large
/// (print_work_estimate).
void print_pipeline_estimate(const Workbench& wb, const pipeline::PipelineOptions& po) {
  const auto& grid = wb.scene.grid;
  const auto& teeth = po.teeth.empty() ? grid.teeth : po.teeth;
  const long long flanks = 2LL * static_cast<long long>(teeth.empty() ? wb.setup.geometry().teeth() : teeth.size());
  const long long per_flank = static_cast<long long>(grid.rows) * grid.cols + grid.profile_points + grid.helix_points;
  print_work_estimate(flanks * per_flank, flanks, po.method == grinding::Method::Exact, 2);
}

void print_summary(const fs::path& dir, const pipeline::PipelineResult& r) {
  const auto& cb = r.iso_before.evaluation.classification;
  const auto& ca = r.iso_after.evaluation.classification;
  if (r.prediction) { // the after-state as a band (docs/monte-carlo.md), never the model's own ≈ 0
    for (const auto& l : report::prediction_lines(*r.prediction)) std::cout << l << "\n";
    const auto imp = report::predicted_improvement(*r.prediction);
    for (const auto& i : imp)
      if (i.name == "largest_abs_um")
        std::cout << fmt::format("Predicted improvement of the largest |deviation|: {} (medians; interval: the after-state's "
                                 "95 % interval against the before-median; every quantity in iso1328.json)\n",
                                 report::improvement_text(i));
  } else {
    std::cout << fmt::format("Largest |deviation| ({} grids, all teeth): {:.2f} µm before; {}: {:.2f} µm (no prediction: "
                             "--samples 0, so no improvement figure)\n",
                             pipeline::grid_label(r), r.largest_before_um, report::kNominalLabel, r.largest_after_um);
    std::cout << fmt::format("ISO 1328-1 overall flank tolerance class: {} before; {}: {}{}\n",
                             evaluation::class_label(cb.overall), report::kNominalLabel, evaluation::class_label(ca.overall),
                             cb.refusal ? fmt::format(" (no class: ISO 1328-1:2013 does not apply to this gear: {})", *cb.refusal)
                             : cb.governing ? fmt::format(" (before: set by {})", evaluation::symbol(*cb.governing))
                                            : std::string());
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
    measurement::KlingelnbergOptions mka;
    workbench::IsoOptions iso;
    MonteCarloFlags mc;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("report", "Figures (PNG, rendered off-screen) and an offline index.html: topology, "
                                               "traces, pitch, machine errors, before/after, measured vs model, diagnosis");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML)")->required();
  add_measurement_options(cmd, opt->measured, opt->mka, false);
  cmd->add_option("--out", opt->out, "Output directory")->required()->check(non_empty_path());
  add_iso_options(cmd, opt->iso);
  add_monte_carlo_options(cmd, opt->mc, false);
  cmd->callback([&action, opt] {
    action = [opt] {
      const output::RunFiles files = report_files(opt->scene, opt->measured);
      output::check_run_files(opt->out, files); // before any work: no input and no user's file is replaced
      const Workbench wb(opt->scene);
      const fs::path dir(opt->out);
      output::OutputFolder folder(dir, files);
      pipeline::PipelineOptions po;
      po.measured_file = measured_of(wb, opt->measured);
      refuse_mka_flags_without_export(po.measured_file);
      po.measurement_format = opt->mka;
      po.iso = opt->iso;
      po.prediction = prediction_options(opt->mc);
      print_pipeline_estimate(wb, po);
      StageProgress progress(po, opt->mc.max_time_s);
      BeforeFigures before(po, wb, dir);
      const auto r = pipeline::run_pipeline(wb, po);
      progress.finish();
      if (r.measurement)
        for (const auto& w : r.measurement->warnings) say("geartopo: warning: " + w);
      write_data_files(dir, opt->scene, wb, r); // the page names them (corrections.csv, scene_with_effect.yaml …)
      const auto figs = report::write_report(dir, wb, r, {}, before.take());
      std::cout << fmt::format("wrote {} figures and {}\n", figs.size(), (dir / "index.html").string());
      finish_output_folder(folder);
      return 0;
    };
  });
}

void register_run_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, out, measured, teeth, method = "flank", simulation = "exact";
    double step = 2.0, noise = 0.0;
    measurement::KlingelnbergOptions mka;
    workbench::IsoOptions iso;
    MonteCarloFlags mc;
    bool json = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("run", "The main job: simulate, evaluate (ISO 1328-1), compensate, compare and diagnose "
                                            "when there is a measurement, and write the report");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML)")->required();
  cmd->add_option("--out", opt->out, "Output directory (created; what an earlier run wrote there and this one does not is removed)")
      ->required()
      ->check(non_empty_path());
  add_measurement_options(cmd, opt->measured, opt->mka, false);
  cmd->add_option("--teeth", opt->teeth, "Teeth to simulate: all (default, or the scene's list) or e.g. 1,18");
  cmd->add_option("--method", opt->method, "Compensation: paper, flank (default) or cycle (as `geartopo compensate`)")
      ->check(CLI::IsMember({"paper", "flank", "cycle"}));
  cmd->add_option("--simulation", opt->simulation, "Simulation of the topology: exact (default) or linear (first order)")
      ->check(CLI::IsMember({"exact", "linear"}));
  cmd->add_option("--step", opt->step, "Correction table spacing along each stroke, mm (default 2)")->check(finite_in(0.05, 50.0));
  cmd->add_option("--noise-um", opt->noise, "Probe noise σ of the measurement, µm (default: estimated from the residual)")
      ->check(probe_sigma_um());
  add_iso_options(cmd, opt->iso);
  add_monte_carlo_options(cmd, opt->mc, false);
  cmd->add_flag("--json", opt->json,
                "Print one JSON object on stdout instead of the text summary: iso1328.json's content, the report's path "
                "and, with a measurement, the comparison's RMS, the verdict and the chosen effect");
  CLI::Option* teeth = cmd->get_option("--teeth");
  cmd->callback([&action, opt, teeth] {
    const bool teeth_given = teeth->count() > 0;
    action = [opt, teeth_given] {
      JsonSummary json(opt->json);
      const output::RunFiles files = report_files(opt->scene, opt->measured);
      output::check_run_files(opt->out, files); // before any work: no input and no user's file is replaced
      // --teeth stands in for the scene's measurement.teeth: simulated, shown in the figures and the page.
      scene::Scene sc = scene::load_scene(opt->scene);
      if (teeth_given) sc.grid.teeth = parse_teeth(opt->teeth, sc.gear.teeth);
      const Workbench wb(std::move(sc));
      pipeline::PipelineOptions po;
      po.method = opt->simulation == "linear" ? grinding::Method::Linear : grinding::Method::Exact;
      refuse_paper_on_a_designed_helix(opt->method, wb);
      po.compensation = opt->method == "paper"   ? compensation::Method::Paper
                        : opt->method == "cycle" ? compensation::Method::Cycle
                                                 : compensation::Method::Flank;
      po.step_mm = opt->step;
      po.noise_um = opt->noise;
      po.measured_file = measured_of(wb, opt->measured);
      refuse_mka_flags_without_export(po.measured_file);
      po.measurement_format = opt->mka;
      po.iso = opt->iso;
      po.prediction = prediction_options(opt->mc);
      const fs::path dir(opt->out);
      output::OutputFolder folder(dir, files);
      if (!quiet()) say("geartopo run: " + (wb.scene.name.empty() ? opt->scene : wb.scene.name));
      print_notes(wb);
      print_pipeline_estimate(wb, po);
      StageProgress progress(po, opt->mc.max_time_s);
      BeforeFigures before(po, wb, dir);
      const auto r = pipeline::run_pipeline(wb, po);
      progress.finish();
      if (r.measurement)
        for (const auto& w : r.measurement->warnings) say("geartopo: warning: " + w);
      nlohmann::json summary = write_data_files(dir, opt->scene, wb, r);
      report::write_report(dir, wb, r, {}, before.take());
      print_summary(dir, r);
      finish_output_folder(folder);
      summary["report"] = (dir / "index.html").string();
      if (r.measurement) {
        const auto& d = r.measurement->diagnosis;
        summary["measurement"] = {{"file", r.measurement->file},
                                  {"residual_rms_um", r.measurement->before.summary.overall.rms_um},
                                  {"noise_um", r.measurement->before.noise_um},
                                  {"chosen", d.chosen ? nlohmann::json(d.chosen->name()) : nlohmann::json(nullptr)},
                                  {"ambiguous", !d.rivals.empty()},
                                  {"verdict", d.verdict}};
      }
      json.emit(summary);
      return 0;
    };
  });
}

} // namespace geartopo::app
