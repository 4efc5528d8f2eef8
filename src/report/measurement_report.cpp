#include "geartopo/report/measurement_report.hpp"

#include "geartopo/files/atomic_write.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <sstream>

namespace geartopo::report {
namespace {

nlohmann::json estimate_json(const diagnosis::Estimate& e) { return {{"value", e.value}, {"standard_error", e.standard_error}}; }

nlohmann::json stats_json(const diagnosis::ResidualStats& s) {
  return {{"points", s.points}, {"rms_um", s.rms_um}, {"max_abs_um", s.max_abs_um}, {"extreme_um", s.extreme_um}};
}

nlohmann::json wave_json(const diagnosis::WavinessScan& w) {
  if (!w.wave) return nullptr;
  return {{"amplitude_um", estimate_json(w.wave->amplitude_um)}, {"wavelength_mm", w.wave->wavelength_mm},
          {"first_crest_mm", w.wave->first_crest_mm}};
}

} // namespace

void write_residuals_csv(const std::filesystem::path& file, const std::vector<measurement::MeasuredPoint>& points,
                         const diagnosis::Comparison& c) {
  output::write_atomically(file, [&](std::ostream& csv) {
    // measured_um and model_um are deviations from the scene's design, which design_um gives (docs/modifications.md).
    csv << "tooth,flank,row,col,diameter_mm,z_mm,measured_um,model_um,residual_um,source_line,point_id,design_um\n";
    for (size_t i = 0; i < points.size(); ++i)
      csv << fmt::format("{},{},{},{},{:.6f},{:.6f},{:.4f},{:.4f},{:.4f},{},{},{:.4f}\n", points[i].tooth,
                         gears::to_string(points[i].flank), points[i].row, points[i].col, points[i].diameter_mm,
                         points[i].z_mm, points[i].deviation_um, c.model_um[i], c.residual_um[i], points[i].line,
                         points[i].id, points[i].design_um);
  });
}

nlohmann::json compare_json(const std::string& scene, const std::string& measured,
                            const std::vector<measurement::MeasuredPoint>& points, const diagnosis::Comparison& comparison) {
  nlohmann::json j;
  j["scene"] = scene;
  j["measured"] = measured;
  j["units"] = "µm; residual = measured − model, along the flank normal, plus material positive; the model's nominal "
               "flank is at the mean tooth-thickness allowance";
  j["nominal_offset_at_mean_allowance_um"] = comparison.allowance_offset_um;
  j["points_without_grid_indices"] = std::count_if(points.begin(), points.end(), [](const auto& p) { return p.row == 0; });
  const auto& n = comparison.counts;
  // Every statistic below is over the "used" points; read = used + outside_evaluation_range + duplicates.
  j["point_counts"] = {{"read", n.read},
                       {"used", n.used},
                       {"outside_evaluation_range", n.outside_evaluation_range},
                       {"duplicates", n.duplicates},
                       {"undefined_values", n.undefined_values},
                       {"off_flank_points", n.off_flank_points},
                       {"sentence", diagnosis::describe_point_counts(n)}};
  j["noise_um"] = comparison.noise_um;
  j["noise_estimated"] = comparison.noise_estimated;
  // diagnosis.json's record of the same name (docs/diagnosis.md, "The verdict as data"), with its sentence.
  if (const auto& d = comparison.reference_in_doubt) {
    nlohmann::json numbers = nlohmann::json::object();
    for (const auto& [key, value] : d->numbers) numbers[key] = value;
    j["reference_in_doubt"] = {{"numbers", numbers}, {"sentence", diagnosis::to_text(*d)}};
  } else {
    j["reference_in_doubt"] = nullptr;
  }
  j["noise_source"] = comparison.noise_source.empty() ? nlohmann::json(nullptr) : nlohmann::json(comparison.noise_source);
  j["overall"] = stats_json(comparison.summary.overall);
  nlohmann::json flanks = nlohmann::json::array();
  for (size_t f = 0; f < comparison.flanks.size(); ++f) {
    nlohmann::json fj;
    fj["tooth"] = comparison.flanks[f].tooth;
    fj["flank"] = diagnosis::to_string(comparison.flanks[f].side);
    fj["stats"] = stats_json(comparison.summary.flanks[f].stats);
    fj["points_outside_evaluation_range"] = comparison.summary.flanks[f].points_outside_range;
    fj["duplicates"] = comparison.flank_duplicates.empty() ? 0 : comparison.flank_duplicates[f];
    const bool disputed = f < comparison.disputed_sign.size() && comparison.disputed_sign[f];
    if (comparison.has_patterns[f]) {
      const auto& p = comparison.patterns[f];
      fj["patterns"] = {{"offset_um", estimate_json(p.offset_um)},
                        {"profile_slope_um", estimate_json(p.profile_slope_um)},
                        {"helix_slope_um", estimate_json(p.helix_slope_um)},
                        {"twist_um", estimate_json(p.twist_um)},
                        {"profile_crowning_um", estimate_json(p.profile_crowning_um)},
                        {"helix_crowning_um", estimate_json(p.helix_crowning_um)},
                        {"waviness_along_profile", wave_json(p.waviness_profile)},
                        {"waviness_along_helix", wave_json(p.waviness_helix)},
                        {"waviness_scanned", {{"along_profile", p.waviness_profile.scanned}, {"along_helix", p.waviness_helix.scanned}}},
                        {"rms_unexplained_um", p.rms_unexplained_um}};
      fj["description"] = diagnosis::describe_patterns(p) + (disputed ? diagnosis::kDisputedSignNote : "");
    }
    fj["rests_on_disputed_sign"] = disputed;
    flanks.push_back(fj);
  }
  j["flanks"] = flanks;
  nlohmann::json teeth = nlohmann::json::array();
  for (const auto& t : comparison.summary.teeth) teeth.push_back({{"tooth", t.tooth}, {"stats", stats_json(t.stats)}});
  j["teeth"] = teeth;
  nlohmann::json trends = nlohmann::json::array();
  for (const auto& s : comparison.trends)
    for (const auto& t : s.trends) trends.push_back({{"flank", diagnosis::to_string(s.side)}, {"sentence", t.sentence}});
  j["tooth_to_tooth"] = trends;
  // What the residual follows (docs/diagnosis.md): each process variable alone, the set-up terms fitted alongside.
  nlohmann::json follows = nlohmann::json::array();
  for (const auto& d : comparison.follows.variables) {
    nlohmann::json f{{"variable", d.variable},
                     {"unit", d.unit},
                     {"law", d.once_per_revolution ? "once_per_revolution" : "linear"},
                     {"explained_fraction", d.explained_fraction},
                     {"delta_bic", d.delta_bic},
                     {"significant", d.significant},
                     {"range", {d.lo, d.hi}},
                     {"sentence", d.sentence}};
    if (d.once_per_revolution) {
      f["amplitude_um"] = d.slope_um, f["amplitude_sd_um"] = d.slope_sd_um, f["phase_deg"] = d.phase_deg,
      f["phase_sd_deg"] = d.phase_sd_deg;
    } else {
      f["slope_um_per_unit"] = d.slope_um, f["slope_sd_um_per_unit"] = d.slope_sd_um;
    }
    follows.push_back(f);
  }
  j["residual_follows"] = follows;
  nlohmann::json regions = nlohmann::json::array();
  for (const auto& r : comparison.regions) regions.push_back(r.sentence);
  j["failing_regions"] = regions;
  nlohmann::json agreement = nlohmann::json::array();
  for (const auto& a : comparison.line_agreement)
    agreement.push_back({{"tooth", a.tooth},
                         {"flank", diagnosis::to_string(a.side)},
                         {"crossings", a.crossings},
                         {"mean_profile_minus_helix_um", a.mean_difference_um},
                         {"max_abs_profile_minus_helix_um", a.max_abs_difference_um},
                         {"disagree", a.disagree},
                         {"sentence", a.sentence.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.sentence)}});
  j["line_crossings"] = agreement;
  return j;
}

std::string compare_summary_text(const diagnosis::Comparison& c) {
  std::string s = diagnosis::describe_point_counts(c.counts) + "\n";
  // First, as diagnose's verdict opens with it: everything below rests on the reference as read.
  if (c.reference_in_doubt) s += "Warning: " + diagnosis::to_text(*c.reference_in_doubt) + "\n";
  const auto& o = c.summary.overall;
  s += fmt::format("Residual (measured − model) over the {} used points on {} flanks: {:.2f} µm RMS, extreme {:+.2f} µm "
                   "(tooth {} {}, L_y {:.2f} mm, z {:.2f} mm); noise {:.{}f} µm{}\n",
                   o.points, c.flanks.size(), o.rms_um, o.extreme_um, o.extreme_tooth, diagnosis::to_string(o.extreme_side),
                   o.extreme_xi_mm, o.extreme_z_mm, c.noise_um, c.noise_um < 0.1 ? 3 : 2,
                   c.noise_estimated ? " (" + c.noise_source + ")" : "");
  s += fmt::format("Model: nominal flank at mean allowance {:+.2f} µm (along the normal, every flank)\n", c.allowance_offset_um);
  for (size_t f = 0; f < c.flanks.size(); ++f) {
    const auto& fs = c.summary.flanks[f];
    s += fmt::format("  tooth {:>3} {:<5}  {:>5} points used ({} outside, {} duplicates)  RMS {:6.2f} µm  extreme {:+7.2f} µm\n",
                     c.flanks[f].tooth, diagnosis::to_string(c.flanks[f].side), fs.stats.points, fs.points_outside_range,
                     c.flank_duplicates.empty() ? 0 : c.flank_duplicates[f], fs.stats.rms_um, fs.stats.extreme_um);
  }
  if (c.regions.empty())
    s += "Where the model fails: nowhere above 3σ of the noise.\n";
  else {
    s += "Where the model fails (|residual| > 3σ):\n";
    for (const auto& r : c.regions) s += "  " + r.sentence + "\n";
  }
  for (const auto& a : c.line_agreement)
    if (a.disagree) s += "Warning: " + a.sentence + "\n";
  s += "Patterns of the residual:\n";
  for (size_t f = 0; f < c.flanks.size(); ++f)
    if (c.has_patterns[f])
      s += "  " + diagnosis::describe_patterns(c.patterns[f]) +
           (f < c.disputed_sign.size() && c.disputed_sign[f] ? diagnosis::kDisputedSignNote : "") + "\n";
  for (const auto& side : c.trends)
    for (const auto& t : side.trends)
      if (!t.sentence.empty()) s += "  " + t.sentence + "\n";
  if (!c.follows.variables.empty()) {
    s += "What the residual follows (each process variable alone, set-up terms removed; strongest first):\n";
    for (const auto& d : c.follows.variables) s += "  " + d.sentence + (d.significant ? "" : " — not significant") + "\n";
  }
  return s;
}

} // namespace geartopo::report
