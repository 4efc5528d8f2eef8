#include "app/report_command.hpp"

#include "app/commands.hpp"
#include "app/parsers.hpp"
#include "app/validators.hpp"

#include <CLI/CLI.hpp>

#include <memory>

namespace geartopo::app {

void register_report_command(CLI::App& app, Action& action) {
  auto opt = std::make_shared<ReportOptions>();
  CLI::App* cmd = app.add_subcommand("report", "Figures (PNG, rendered off-screen) and an offline index.html: topology, "
                                               "traces, pitch, machine errors, before/after, measured vs model, diagnosis; "
                                               "or, given a series file, the production series' page (docs/series.md)");
  cmd->add_option("SCENE", opt->scene, "Scene file (YAML), or a series file (docs/scene-format.md \"Series files\")")->required();
  add_measurement_options(cmd, opt->measured, opt->mka, false);
  cmd->add_option("--out", opt->out, "Output directory")->required()->check(non_empty_path());
  add_iso_options(cmd, opt->iso);
  add_monte_carlo_options(cmd, opt->mc, false);
  cmd->callback([&action, opt, cmd] {
    for (const CLI::Option* o : cmd->get_options())
      if (o->count() > 0 && o->get_name() != "SCENE" && o->get_name() != "--out") opt->other_flags_given.push_back(o->get_name());
    action = [opt] { return run_report(*opt); };
  });
}

} // namespace geartopo::app
