// geartopo synth: synthetic measurements of a truth scene, with hidden effects.
#include "app/synth_command.hpp"

#include "app/commands.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_synth_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<SynthFlags>();
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
  cmd->callback([&action, opt] { action = [opt] { return run_synth(*opt); }; });
}

} // namespace geartopo::app
