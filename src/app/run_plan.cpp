// geartopo plan's work (measured_commands.hpp): the diagnosis' measurement plan, printed and in plan.json.
#include "app/messages.hpp"
#include "app/progress.hpp"
#include "app/run_measured.hpp"

#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/output_folder.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <iostream>
#include <optional>

namespace geartopo::app {
namespace {

void print_plan(const diagnosis::Diagnosis& d) {
  if (!d.plan) {
    std::cout << (d.chosen ? fmt::format("Not ambiguous: {} is ahead of every other explanation by more than the "
                                         "ΔBIC threshold; nothing more to measure to decide.\n",
                                         d.chosen->name())
                           : std::string("No effect of the library is significant: nothing to decide between.\n"));
    return;
  }
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
    std::cout << fmt::format("  {:>5} {:>10.2f} {:>12.3f}  {} flank, row {}, column {}\n", t.tooth, t.separation_sigma,
                             t.max_difference_um, t.flank == Flank::Left ? "left" : "right", t.row, t.col);
}

} // namespace

int run_plan(const PlanFlags& opt) {
  const output::RunFiles files{{opt.scene, opt.measured}, {"plan.json"}};
  std::optional<output::OutputFolder> folder; // locked and staged before any work: a second run is refused now
  if (!opt.out.empty()) folder.emplace(opt.out, files);
  const LoadedScene scene = load_scene_for(opt);
  const auto pts = read_measured_points(*scene.wb, opt.measured, opt.mka);
  commands::DiagnoseRequest request;
  request.noise_um = opt.noise;
  if (opt.layout == "traces") request.layout = diagnosis::DiagnoseOptions::PlanLayout::Traces;
  Progress progress("diagnose", 0, "candidate fits");
  request.on_candidate_fitted = progress.callback();
  const auto r = commands::plan(scene.input(), {pts, opt.measured, {}}, request, cli_argument_names());
  progress.finish();
  print_plan(r.diagnosis);
  if (!opt.out.empty()) {
    const std::filesystem::path out(opt.out);
    output::write_text_atomically(out / "plan.json", r.json.dump(2) + "\n");
    std::cout << "wrote " << (out / "plan.json").string() << "\n";
    finish_output_folder(*folder);
  }
  return 0;
}

} // namespace geartopo::app
