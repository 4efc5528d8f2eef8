#include "geartopo/diagnosis/compare.hpp"

#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/prediction.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>

namespace geartopo::diagnosis {
Comparison compare(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                   const std::vector<MeasuredPoint>& pts, double noise_um) {
  if (pts.empty()) throw std::invalid_argument("compare: no measured points");
  // estimate_noise_um uses flanks of 10 points or more and otherwise falls back to a fixed 0.1 µm: with fewer points
  // in all, the "estimate" would be that constant, printed as if measured (issue 18: one point gave "noise 0.10 µm
  // (estimated)").
  constexpr std::size_t kMinPointsToEstimateNoise = 10;
  if (noise_um <= 0.0 && pts.size() < kMinPointsToEstimateNoise)
    throw std::invalid_argument(fmt::format("compare: estimating the probe noise needs at least {} measured points, the "
                                            "measurement has {}: give the noise (--noise-um)",
                                            kMinPointsToEstimateNoise, pts.size()));
  Comparison c;
  c.model_um = predict(setup, model, pts, grinding::Method::Exact);
  c.allowance_offset_um = mean_allowance_offset_um(setup.geometry());
  c.residual_um.resize(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) c.residual_um[i] = pts[i].deviation_um - c.model_um[i];
  c.noise_estimated = noise_um <= 0.0;
  c.noise_um = c.noise_estimated ? estimate_noise_um(pts, c.residual_um) : noise_um;

  c.flanks = flank_residuals(setup.ranges(), pts, c.residual_um, &c.flank_point_index);

  PatternOptions po;
  po.noise_um = c.noise_um;
  RegionOptions ro;
  ro.noise_um = c.noise_um;
  // A lone point beyond 3σ is what noise gives 0.27 % of the points (0.7 of the 252 of two measured teeth): listed
  // beside a whole-flank region it read as a finding (issue 17). Regions need two points here.
  ro.min_points = 2;
  std::map<int, std::vector<FlankPatterns>> by_side;
  for (const auto& f : c.flanks) {
    try {
      c.patterns.push_back(fit_flank_patterns(f, po));
      c.has_patterns.push_back(true);
      by_side[static_cast<int>(f.side)].push_back(c.patterns.back());
    } catch (const std::invalid_argument&) { // too few distinct positions on this flank for the six patterns
      c.patterns.emplace_back();
      c.has_patterns.push_back(false);
    }
    for (auto& reg : find_failing_regions(f, ro)) c.regions.push_back(std::move(reg));
  }
  for (const auto& [side, list] : by_side)
    if (list.size() >= 2) c.trends.push_back(fit_tooth_trends(list, setup.geometry().teeth()));
  c.summary = summarize_residuals(c.flanks);
  if (pts.size() >= 4) c.follows = residual_dependence(setup, pts, c.residual_um);
  return c;
}

std::vector<FlankResiduals> flank_residuals(const gears::EvaluationRanges& r, const std::vector<MeasuredPoint>& pts,
                                            const std::vector<double>& residual_um,
                                            std::vector<std::vector<size_t>>* point_index) {
  std::map<std::pair<int, int>, size_t> index;
  std::vector<FlankResiduals> flanks;
  std::vector<std::vector<size_t>> members;
  for (size_t i = 0; i < pts.size(); ++i) {
    const auto key = std::make_pair(pts[i].tooth, static_cast<int>(pts[i].flank));
    auto [it, fresh] = index.try_emplace(key, flanks.size());
    if (fresh) {
      FlankResiduals f;
      f.tooth = pts[i].tooth;
      f.side = pts[i].flank;
      f.xi_start_mm = r.xi_eval_start_mm, f.xi_end_mm = r.xi_eval_end_mm, f.z_start_mm = r.z_eval_start_mm, f.z_end_mm = r.z_eval_end_mm;
      flanks.push_back(f);
      members.emplace_back();
    }
    flanks[it->second].points.push_back({pts[i].roll_length_mm, pts[i].z_mm, residual_um[i]});
    members[it->second].push_back(i);
  }
  // Order flanks by tooth, then left before right (the map's order).
  std::vector<FlankResiduals> ordered;
  std::vector<std::vector<size_t>> ordered_index;
  for (const auto& [key, k] : index) ordered.push_back(std::move(flanks[k])), ordered_index.push_back(std::move(members[k]));
  if (point_index) *point_index = std::move(ordered_index);
  return ordered;
}

} // namespace geartopo::diagnosis
