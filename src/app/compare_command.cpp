// geartopo compare: measured − model, where the model fails, and the residual's patterns.
#include "app/commands.hpp"
#include "app/measured_commands.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_compare_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<CompareFlags>();
  CLI::App* cmd = app.add_subcommand("compare", "Measured − model (µm) at every measured point: statistics, where the model "
                                                "fails, and the residual's patterns");
  cmd->add_option("SCENE", opt->scene, "Model scene (YAML)")->required();
  add_measurement_options(cmd, opt->measured, opt->mka);
  cmd->add_option("--out", opt->out, "Output directory: compare.json, residuals.csv")->required()->check(non_empty_path());
  cmd->add_option("--noise-um", opt->noise, "Probe noise σ in µm (default: estimated)")->check(probe_sigma_um());
  cmd->add_flag("--json", opt->json, "Print compare.json's content on stdout instead of the text summary");
  cmd->callback([&action, opt] { action = [opt] { return run_compare(*opt); }; });
}

} // namespace geartopo::app
