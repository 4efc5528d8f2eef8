#include "app/evaluate_command.hpp"

#include "app/commands.hpp"
#include "app/parsers.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_evaluate_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<EvaluateOptions>();
  CLI::App* cmd = app.add_subcommand("evaluate", "ISO 1328-1:2013 deviations (µm) and flank tolerance classes of the "
                                                 "simulated gear, or of measured traces");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML)")->required();
  cmd->add_option("--out", opt->out, "Output directory (created): iso1328.json")->required()->check(non_empty_path());
  cmd->add_option("--method", opt->method, "exact or linear simulation")->check(CLI::IsMember({"exact", "linear"}));
  cmd->add_option("--traces", opt->traces, "Evaluate measured traces instead: traces CSV (docs/grinding.md) or Klingelnberg "
                                           "export (docs/measurement-formats.md), told apart by content");
  cmd->add_option("--machine-values", opt->machine_values,
                  "With --traces EXPORT.mka: the measuring machine's value file (.mew, HEADER KS.MW.FILE) written beside "
                  "it; its f_Hα, f_fα, F_α, f_Hβ, f_fβ, F_β per tooth and flank are printed beside geartopo's evaluation "
                  "of the same traces, a difference above 0.1 µm flagged with its likely cause "
                  "(docs/measurement-formats.md). Never read unless given")
      ->check(non_empty_path());
  cmd->add_option("--prediction", opt->prediction,
                  "prediction.json of geartopo compensate: print each quantity beside its predicted median and 95 % "
                  "interval and whether it lies inside (a report, not a gate: the exit code does not depend on it); "
                  "the measurement is evaluated with the ISO options the prediction records")
      ->check(non_empty_path());
  cmd->add_option("--prediction-side", opt->side,
                  "after (default: the gear ground with the corrections) or before (without them)")
      ->check(CLI::IsMember({"before", "after"}));
  cmd->add_option("--aqdef", opt->aqdef, "Also write the ISO 1328-1 values per tooth and flank as an AQDEF file (.dfq, "
                                         "docs/aqdef.md) for the quality system")
      ->check(non_empty_path());
  cmd->add_option("--before-traces", opt->before_traces,
                  "With --prediction and --traces (gear 2, ground with the corrections): the traces of gear 1, ground "
                  "without them, evaluated alike and checked against the prediction's before band; "
                  "against_prediction.png marks both gears")
      ->check(non_empty_path());
  add_iso_options(cmd, opt->iso);
  add_measured_against_option(cmd, opt->mka); // --traces and --before-traces
  add_klingelnberg_options(cmd, opt->mka);
  const CLI::Option* direction_flag = cmd->get_option("--iso-direction");
  const CLI::Option* sign_flag = cmd->get_option("--helix-slope-sign");
  cmd->callback([&action, opt, direction_flag, sign_flag] {
    opt->iso_direction_given = direction_flag->count() > 0;
    opt->helix_slope_sign_given = sign_flag->count() > 0;
    action = [opt] { return run_evaluate(*opt); };
  });
}

} // namespace geartopo::app
