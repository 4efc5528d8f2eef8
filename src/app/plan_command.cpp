// geartopo plan: what to measure next when the measurement cannot tell two explanations apart (docs/diagnosis.md,
// "Ambiguity and what to measure next"). Runs the diagnosis and prints/writes its measurement plan.
#include "app/commands.hpp"
#include "app/measurement_options.hpp"
#include "app/messages.hpp"
#include "app/progress.hpp"
#include "app/validators.hpp"
#include "geartopo/diagnosis/diagnosis_json.hpp"
#include "geartopo/files/output_folder.hpp"
#include "geartopo/report/measurement_report.hpp"

#include "geartopo/files/atomic_write.hpp"
#include "geartopo/diagnosis/compare.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <CLI/CLI.hpp>
#include <optional>
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

namespace geartopo::app {

void register_plan_command(CLI::App& app, Action& action) {
  struct Options {
    std::string scene, measured, out;
    double noise = 0.0;
    std::string layout = "grid";
    KlingelnbergFlags mka;
  };
  auto opt = std::make_shared<Options>();
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
  cmd->callback([&action, opt] {
    action = [opt] {
      const output::RunFiles files{{opt->scene, opt->measured}, {"plan.json"}};
      std::optional<output::OutputFolder> folder; // locked and staged before any work: a second run is refused now
      if (!opt->out.empty()) folder.emplace(opt->out, files);
      const workbench::Workbench wb(opt->scene);
      const auto pts = read_measured_points(wb, opt->measured, opt->mka);
      diagnosis::DiagnoseOptions o;
      o.noise_um = opt->noise;
      if (opt->layout == "traces") o.plan_layout = diagnosis::DiagnoseOptions::PlanLayout::Traces;
      Progress progress("diagnose", 0, "candidate fits");
      o.on_candidate_fitted = progress.callback();
      const auto d = diagnosis::diagnose(wb.setup, wb.process(), pts, wb.effect_types(), o);
      progress.finish();
      const nlohmann::json j = diagnosis::plan_json(opt->scene, opt->measured, d);
      if (!d.plan) {
        std::cout << (d.chosen ? fmt::format("Not ambiguous: {} is ahead of every other explanation by more than the "
                                             "ΔBIC threshold; nothing more to measure to decide.\n",
                                             d.chosen->name())
                               : std::string("No effect of the library is significant: nothing to decide between.\n"));
      } else {
        const auto& p = *d.plan;
        std::cout << fmt::format("Ambiguous between {} and {} (ΔBIC gap {:.1f}).\n", p.first, p.second, p.delta_bic_gap);
        const auto& r = p.recommended;
        std::cout << fmt::format("{} teeth {} with {}: expected ΔBIC gap after refit {:.0f} if {} "
                                 "is right, {:.0f} if {} is (noise {:.2f} µm).\n",
                                 r.resolves ? "Measure" : "Not enough, the closest: measure", fmt::join(r.teeth, ","),
                                 diagnosis::what_to_measure(r), r.delta_bic_if_first, p.first, r.delta_bic_if_second, p.second,
                                 p.noise_um);
        std::cout << fmt::format("  {:>5} {:>10} {:>12}  {}\n", "tooth", "sep (σ)", "max |Δ| µm", "where");
        for (const auto& t : p.teeth)
          std::cout << fmt::format("  {:>5} {:>10.2f} {:>12.3f}  {} flank, row {}, column {}\n", t.tooth,
                                   t.separation_sigma, t.max_difference_um, t.flank == Flank::Left ? "left" : "right",
                                   t.row, t.col);
      }
      if (!opt->out.empty()) {
        const std::filesystem::path out(opt->out);
        output::write_text_atomically(out / "plan.json", j.dump(2) + "\n");
        std::cout << "wrote " << (out / "plan.json").string() << "\n";
        finish_output_folder(*folder);
      }
      return 0;
    };
  });
}

} // namespace geartopo::app
