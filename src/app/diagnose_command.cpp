// geartopo diagnose: which physical effect the model is missing, and the scene with it added.
#include "app/commands.hpp"
#include "app/measured_commands.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_diagnose_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<DiagnoseFlags>();
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
  cmd->callback([&action, opt] { action = [opt] { return run_diagnose(*opt); }; });
}

} // namespace geartopo::app
