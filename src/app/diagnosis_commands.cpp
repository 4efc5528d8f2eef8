// geartopo synth / diagnose: synthetic measurements with hidden effects, and finding what a model is missing.
#include "app/commands.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/input_registry.hpp"
#include "app/json_summary.hpp"
#include "app/measurement_options.hpp"
#include "app/messages.hpp"
#include "app/parsers.hpp"
#include "app/progress.hpp"
#include "app/validators.hpp"
#include "geartopo/files/output_folder.hpp"
#include "geartopo/diagnosis/diagnosis_json.hpp"
#include "geartopo/report/measurement_report.hpp"

#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/identified_effects.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/diagnosis/scene_writer.hpp"
#include "geartopo/diagnosis/stroke_scatter.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/compensation/compensator.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/core/uncertain_value.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/pipeline/monte_carlo.hpp"
#include "geartopo/pipeline/synth_corrections.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace geartopo::app {

void register_synth_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, out, teeth = "1,18", format = "csv", corrections;
    double noise = 0.5;
    std::uint64_t seed = 1;
    bool stroke_scatter = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("synth", "Synthetic CMM measurement (topology CSV, µm) of a truth scene, with "
                                              "Gaussian probe noise");
  cmd->add_option("TRUTH_SCENE", opt->scene, "Truth scene (YAML), possibly with effects the model scene lacks")->required();
  cmd->add_option("--out", opt->out,
                  "File to write (topology CSV, a traces CSV with --format traces, or a Klingelnberg export with --format "
                  "klingelnberg); an existing folder or a path ending in '/' is a folder like every other --out: "
                  "measured.csv (traces.csv, measured.mka) inside it")
      ->required()
      ->check(non_empty_path());
  cmd->add_option("--format", opt->format,
                  "csv (topology CSV on the scene's grid, default), traces (one profile and one helix trace per flank, "
                  "the scene's profile_points/helix_points: for geartopo evaluate --traces) or klingelnberg (TOPOGRAFIE "
                  "profile traces, transverse µm, raw sign: docs/measurement-formats.md)")
      ->check(CLI::IsMember({"csv", "traces", "klingelnberg"}));
  cmd->add_option("--teeth", opt->teeth, "Measured teeth, e.g. 1,18 (default) or all");
  cmd->add_option("--noise-um", opt->noise, "Standard deviation of the probe noise, µm (default 0.5)")->check(finite_in(0.0, 1000.0));
  cmd->add_option("--seed", opt->seed, "Random seed, a whole number ≥ 0 (default 1): probe noise and stroke scatter")
      ->check(seed_value());
  cmd->add_flag("--stroke-scatter", opt->stroke_scatter,
                "Each stroke's axis commands off by a draw of the truth scene's machine.repeatability (one standard "
                "deviation R/4 per axis, constant over the stroke), as the Monte Carlo grinds (docs/monte-carlo.md)");
  cmd->add_option("--corrections", opt->corrections,
                  "Grind with these corrections: corrections.csv of geartopo compensate, rounded to the truth scene's "
                  "machine.resolution as the controller takes them (docs/monte-carlo.md)")
      ->check(non_empty_path());
  cmd->callback([&action, opt] {
    action = [opt] {
      const Workbench wb(opt->scene);
      diagnosis::SynthOptions so;
      so.teeth = parse_teeth(opt->teeth, wb.setup.geometry().teeth());
      so.rows = wb.scene.grid.rows;
      so.cols = wb.scene.grid.cols;
      so.noise_um = opt->noise;
      so.seed = opt->seed;
      const auto table = pipeline::synth_corrections(wb, opt->corrections, opt->stroke_scatter, opt->seed);
      std::optional<compensation::CompensatedProcess> corrected;
      if (table) corrected.emplace(wb.process(), *table);
      const grinding::GrindingProcess& process =
          corrected ? static_cast<const grinding::GrindingProcess&>(*corrected) : wb.process();
      // Every other command's --out is a folder: a folder here gets the measurement under a fixed name.
      std::filesystem::path file(opt->out);
      std::error_code ec;
      if (std::filesystem::is_directory(file, ec) || opt->out.back() == '/')
        file /= opt->format == "klingelnberg" ? "measured.mka" : opt->format == "traces" ? "traces.csv" : "measured.csv";
      // Before any work: the scene or the corrections read above are never replaced, and a name too long for the
      // file system or a file where a folder must be is refused in words, not as a std::filesystem error.
      output::check_name_lengths(file);
      output::check_not_an_input(file);
      if (file.has_parent_path()) {
        const auto folder = file.parent_path();
        if (std::filesystem::exists(folder, ec) && !std::filesystem::is_directory(folder, ec))
          throw output::OutputError(file, folder.string() + " is a file, not a folder (a --out ending in '/' names a folder)");
        std::filesystem::create_directories(folder, ec);
        if (ec) throw output::OutputError(file, "cannot create its folder " + folder.string() + ": " + ec.message());
      }
      std::size_t points = 0;
      if (opt->format == "traces") {
        const auto topo = diagnosis::synthesize_traces(wb.setup, process, so, wb.scene.grid.profile_points,
                                                       wb.scene.grid.helix_points);
        for (const auto& ft : topo) points += ft.profile.size() + ft.helix.size();
        output::write_atomically(file, [&](std::ostream& out) { grinding::write_traces_csv(out, topo); });
      } else {
        const auto rows = diagnosis::synthesize(wb.setup, process, so);
        points = rows.size();
        output::write_atomically(file, [&](std::ostream& out) {
          if (opt->format == "klingelnberg")
            measurement::write_klingelnberg(out, wb.setup.geometry(), rows);
          else
            grinding::write_topology_rows(out, rows);
        });
      }
      std::string ground;
      if (!opt->corrections.empty()) ground += ", with the corrections of " + opt->corrections;
      if (opt->stroke_scatter) ground += ", stroke scatter";
      std::cout << fmt::format("wrote {} ({} points, noise {} µm, seed {}{})\n", file.string(), points, opt->noise,
                               opt->seed, ground);
      return 0;
    };
  });
}

void register_diagnose_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, measured, out;
    double noise = 0.0;
    bool json = false, scene_uncertainty = false;
    std::vector<std::string> candidates;
    KlingelnbergFlags mka;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("diagnose", "Which physical effect is the model missing? Fits every library effect "
                                                 "to the residual and writes the scene with the best one added");
  cmd->add_option("SCENE", opt->scene, "Model scene (YAML)")->required();
  add_measurement_options(cmd, opt->measured, opt->mka);
  cmd->add_option("--out", opt->out, "Output directory: diagnosis.json, scene_with_effect.yaml")->required()->check(non_empty_path());
  cmd->add_option("--noise-um", opt->noise, "Probe noise σ in µm (default: estimated from the residual)")
      ->check(probe_sigma_um());
  cmd->add_option("--candidates", opt->candidates, "Effect types to try (default: every library effect not in the scene)")
      ->delimiter(',');
  cmd->add_flag("--json", opt->json, "Print diagnosis.json's content on stdout instead of the text summary");
  cmd->add_flag("--scene-uncertainty", opt->scene_uncertainty,
                "The residual carries the scene's declared uncertainties — machine.repeatability per stroke and the "
                "error map's machine.uncertainty: fit by generalised least squares (docs/diagnosis.md)");
  cmd->callback([&action, opt] {
    action = [opt] {
      JsonSummary json(opt->json);
      const output::RunFiles files{{opt->scene, opt->measured}, {"diagnosis.json", "scene_with_effect.yaml"}};
      output::OutputFolder folder(opt->out, files); // locked and staged before any work: a second run is refused now
      const Workbench wb(opt->scene);
      for (const auto& c : opt->candidates)
        if (!effects::make_effect(c))
          throw CLI::ValidationError("--candidates", fmt::format("'{}' is not an effect of the library ({})", c,
                                                                 fmt::join(effects::effect_types(), ", ")));
      const auto pts = read_measured_points(wb, opt->measured, opt->mka);
      diagnosis::DiagnoseOptions o;
      o.noise_um = opt->noise;
      o.candidates = opt->candidates;
      if (opt->scene_uncertainty) {
        o.stroke_repeatability_sd = wb.scene.machine.uncertainty.repeatability;
        o.model_uncertainty_um = diagnosis::map_sensitivity(wb, pts);
      }
      Progress progress("diagnose", 0, "candidate fits");
      o.on_candidate_fitted = progress.callback();
      const auto d = diagnosis::diagnose(wb.setup, wb.process(), pts, wb.effect_types(), o);
      progress.finish();

      const nlohmann::json j = diagnosis::diagnosis_json(opt->scene, opt->measured, d, diagnosis::mean_allowance_offset_um(wb.setup.geometry()));

      const std::filesystem::path out(opt->out);
      output::write_text_atomically(out / "diagnosis.json", j.dump(2) + "\n");
      std::cout << fmt::format("{} measured points; residual {:.2f} µm RMS; noise {:.2f} µm{}\n", d.points, d.rms_before_um,
                               d.noise_um, d.noise_estimated ? " (estimated)" : "");
      std::cout << fmt::format("Model: nominal flank at mean allowance {:+.2f} µm (along the normal, every flank)\n",
                               diagnosis::mean_allowance_offset_um(wb.setup.geometry()));
      std::cout << fmt::format("  {:<4} {:<16} {:>9} {:>10} {:>10}  {}\n", "rank", "effect", "ΔBIC", "explained", "RMS after",
                               "parameters (± 1σ)");
      int rank = 1;
      for (const auto& c : d.ranked) {
        std::string params;
        for (const auto& p : c.parameters.front())
          if (p.fitted) // GUM §7.2.6; the files keep every digit. A value the data do not fix is no finding.
            params += fmt::format("{} {}  ", p.key, p.determined ? text::with_uncertainty(p.value, p.uncertainty)
                                                                 : std::string("not determined"));
        std::cout << fmt::format("  {:<4} {:<16} {:>9.1f} {:>9.1f}% {:>7.2f} µm  {}{}\n", rank++, c.name(), c.delta_bic,
                                 100.0 * c.explained_fraction, c.rms_after_um, params, c.rejection ? "(rejected: " + diagnosis::to_text(*c.rejection) + ")" : c.significant ? std::string() : std::string("(not significant)"));
      }
      if (d.combination)
        std::cout << fmt::format("  combination: {} (ΔBIC {:.1f}, RMS after {:.2f} µm)\n", d.combination->name(),
                                 d.combination->delta_bic, d.combination->rms_after_um);
      if (!d.hypotheses.empty()) {
        std::cout << "Beyond the library (the chain's error components and each wheel flank; docs/diagnosis.md):\n";
        int k = 1;
        for (const auto& c : d.hypotheses)
          std::cout << fmt::format("  {:<4} {:<34} {:>9.1f} {:>9.1f}%  {}{}\n", k++, c.name(), c.delta_bic,
                                   100.0 * c.explained_fraction, c.description,
                                   c.rejection ? " (rejected: " + diagnosis::to_text(*c.rejection) + ")" : std::string());
      }
      std::cout << d.verdict << "\n";
      if (d.chosen && d.withheld) {
        std::cout << "scene_with_effect.yaml not written: " << diagnosis::to_text(*d.withheld) << "\n";
        std::cout << "wrote " << (out / "diagnosis.json").string() << "\n";
      } else if (d.chosen) {
        const auto comments = diagnosis::identification_comments(*d.chosen, opt->measured);
        const auto change_comments = diagnosis::change_identification_comments(*d.chosen, opt->measured);
        const auto path = out / "scene_with_effect.yaml";
        // With the fit's uncertainties and correlation: a prediction from this scene draws the effect within them.
        const auto identified = diagnosis::identified_effects(d, *d.chosen);
        diagnosis::write_scene_with_effects(opt->scene, identified.effects, comments, path, identified.uncertainties,
                                            identified.correlation, d.chosen->changes, d.chosen->change_sd,
                                            change_comments);
        std::cout << "wrote " << (out / "diagnosis.json").string() << " and " << path.string() << "\n";
      } else {
        std::cout << "wrote " << (out / "diagnosis.json").string() << "\n";
      }
      finish_output_folder(folder);
      json.emit(j);
      return 0;
    };
  });
}

} // namespace geartopo::app
