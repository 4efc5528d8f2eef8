// geartopo diagnose's work (measured_commands.hpp): the ranked explanations printed, diagnosis.json, and the scene
// with the chosen one added.
#include "app/json_summary.hpp"
#include "app/messages.hpp"
#include "app/progress.hpp"
#include "app/run_measured.hpp"

#include "geartopo/core/uncertain_value.hpp"
#include "geartopo/diagnosis/hypothesis_rows.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/files/atomic_write.hpp"
#include "geartopo/files/output_folder.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>

namespace geartopo::app {
namespace {

/// The explanations as ranked: the library's single effects, a combination, and beyond the library. `whitened`: the
/// fits were generalised least squares (--scene-uncertainty), so a candidate's RMS after is of the whitened residual,
/// which the verdict's plain µm RMS are not: the column says so (issue 44: "RMS after 0.29 µm" beside "from 4.11 to
/// 1.86 µm RMS" could not be reconciled).
void print_ranked(const diagnosis::Diagnosis& d, double allowance_offset_um, bool whitened) {
  // As measured, set-up terms included: the verdict's "from … to …" are with them removed.
  std::cout << fmt::format("{} measured points; residual {:.2f} µm RMS as measured (set-up terms included); noise {:.2f} "
                           "µm{}\n",
                           d.points, d.rms_before_um, d.noise_um, d.noise_estimated ? " (estimated)" : "");
  std::cout << fmt::format("Model: nominal flank at mean allowance {:+.2f} µm (along the normal, every flank)\n",
                           allowance_offset_um);
  std::cout << fmt::format("  {:<4} {:<16} {:>9} {:>10} {:>10}  {}\n", "rank", "effect", "ΔBIC", "explained",
                           whitened ? "wRMS after" : "RMS after", "parameters (± 1σ)");
  int rank = 1;
  for (const auto& c : d.ranked) {
    std::string params;
    for (const auto& p : c.parameters.front())
      if (p.fitted) // GUM §7.2.6; the files keep every digit. A value the data do not fix is no finding.
        params += fmt::format("{} {}  ", p.key, p.determined ? text::with_uncertainty(p.value, p.uncertainty)
                                                             : std::string("not determined"));
    const std::string status = c.rejection     ? "(rejected: " + diagnosis::to_text(*c.rejection) + ")"
                               : c.significant ? std::string()
                                               : std::string("(not significant)");
    std::cout << fmt::format("  {:<4} {:<16} {:>9.1f} {:>9.1f}% {:>7.2f} µm  {}{}\n", rank++, c.name(), c.delta_bic,
                             100.0 * c.explained_fraction, c.rms_after_um, params, status);
  }
  if (d.combination)
    std::cout << fmt::format("  combination: {} (ΔBIC {:.1f}, {} after {:.2f} µm)\n", d.combination->name(),
                             d.combination->delta_bic, whitened ? "wRMS" : "RMS", d.combination->rms_after_um);
  if (whitened)
    std::cout << "  wRMS after: RMS of the whitened residual, set-up terms removed (generalised least squares with the "
                 "scene's stroke scatter and map uncertainty: the probe noise σ when the model fits); the verdict's µm "
                 "RMS are of the plain residual\n";
  else
    std::cout << "  RMS after: with the set-up terms removed, as the verdict's\n";
  if (d.hypotheses.empty()) return;
  std::cout << "Beyond the library (the chain's error components and each wheel flank; docs/diagnosis.md):\n";
  int k = 1;
  for (const auto& row : diagnosis::hypothesis_rows(d)) { // an equivalence class is one row, its members in it
    const auto& c = *row.hypothesis;
    std::cout << fmt::format("  {:<4} {:<34} {:>9.1f} {:>9.1f}%  {}{}{}\n", k++, c.name(), c.delta_bic,
                             100.0 * c.explained_fraction, c.description,
                             row.members.empty() ? std::string() : "; " + diagnosis::members_text(row, 8),
                             c.rejection ? " (rejected: " + diagnosis::to_text(*c.rejection) + ")" : std::string());
  }
}

} // namespace

int run_diagnose(const DiagnoseFlags& opt) {
  JsonSummary json(opt.json);
  const output::RunFiles files{{opt.scene, opt.measured}, {"diagnosis.json", "scene_with_effect.yaml"}};
  output::OutputFolder folder(opt.out, files); // locked and staged before any work: a second run is refused now
  const LoadedScene scene = load_scene_for(opt);
  const auto pts = read_measured_points(*scene.wb, opt.measured, opt.mka);
  commands::DiagnoseRequest request;
  request.noise_um = opt.noise;
  request.candidates = opt.candidates;
  request.scene_uncertainty = opt.scene_uncertainty;
  Progress progress("diagnose", 0, "candidate fits");
  request.on_candidate_fitted = progress.callback();
  const std::filesystem::path out(opt.out);
  const auto r = commands::diagnose(scene.input(), {pts, opt.measured, {}}, request, out, cli_argument_names());
  progress.finish();
  const auto& d = r.diagnosis;
  output::write_text_atomically(out / "diagnosis.json", r.json.dump(2) + "\n");
  print_ranked(d, diagnosis::mean_allowance_offset_um(scene.wb->setup.geometry()), opt.scene_uncertainty);
  std::cout << d.verdict << "\n";
  // The user's own effects are named as theirs, with the law they declared (the library's need no introduction).
  for (size_t e = 0; d.chosen && e < d.chosen->effects.size() && e < d.chosen->explanations.size(); ++e)
    if (effects::is_custom_effect(d.chosen->effects[e].type))
      std::cout << d.chosen->effects[e].type << " is " << d.chosen->explanations[e] << "\n";
  // And how alike their fields are to the library's and the machine elements' on these flanks (diagnosis.json: all).
  for (const auto& c : d.ranked) {
    if (c.look_alikes.empty()) continue;
    std::string alike;
    for (size_t k = 0; k < c.look_alikes.size() && k < 3; ++k)
      alike += fmt::format("{}{} {:.3f}", k ? ", " : "", c.look_alikes[k].first, c.look_alikes[k].second);
    std::cout << c.name() << "'s field on these flanks is like (|ρ|, set-up terms removed): " << alike << "\n";
  }
  if (d.chosen && d.withheld) std::cout << "scene_with_effect.yaml not written: " << diagnosis::to_text(*d.withheld) << "\n";
  if (r.scene_with_effect) {
    output::write_text_atomically(out / "scene_with_effect.yaml", *r.scene_with_effect);
    std::cout << "wrote " << (out / "diagnosis.json").string() << " and " << (out / "scene_with_effect.yaml").string() << "\n";
  } else {
    std::cout << "wrote " << (out / "diagnosis.json").string() << "\n";
  }
  finish_output_folder(folder);
  json.emit(r.json);
  return 0;
}

} // namespace geartopo::app
