// geartopo plan: what to measure next when the measurement cannot tell two explanations apart (docs/diagnosis.md,
// "Ambiguity and what to measure next").
#include "app/commands.hpp"
#include "app/measured_commands.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_plan_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<PlanFlags>();
  CLI::App* cmd = app.add_subcommand("plan", "What to measure next: when explanations of the residual are within the "
                                             "ΔBIC threshold of each other, the teeth that tell them apart");
  cmd->add_option("SCENE", opt->scene, "Model scene (YAML)")->required();
  add_measurement_options(cmd, opt->measured, opt->mka);
  cmd->add_option("--out", opt->out, "Output directory: plan.json (default: print only)")->check(non_empty_path());
  cmd->add_option("--noise-um", opt->noise, "Probe noise σ in µm (default: estimated from the residual)")
      ->check(probe_sigma_um());
  cmd->add_option("--layout", opt->layout,
                  "What to measure on the new teeth: grid (7×9 per flank and denser) or traces (3 profile traces at "
                  "face-width positions and 3 helix traces at diameters per flank, 100 points each, as a gear measuring "
                  "machine takes them)")
      ->check(CLI::IsMember({"grid", "traces"}));
  cmd->callback([&action, opt] { action = [opt] { return run_plan(*opt); }; });
}

} // namespace geartopo::app
