#include "geartopo/diagnosis/compare.hpp"

#include "geartopo/core/parallel.hpp"

#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/prediction.hpp"

#include <fmt/format.h>

#include <cmath>
#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

namespace geartopo::diagnosis {
Comparison compare(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                   const std::vector<MeasuredPoint>& pts, double noise_um, const measurement::ReadCounts& read,
                   const std::function<void()>& keep_going) {
  const auto check = [&keep_going] { if (keep_going) keep_going(); };
  if (pts.empty()) throw std::invalid_argument("compare: no measured points");
  // The σ every test and trend divides by: a given one within the bounds diagnose accepts (1e-158 µm made the tooth
  // trends' weights overflow).
  limits::require(limits::noise_um_refusal(noise_um), "compare: noise_um");
  // estimate_noise_um uses flanks of 10 points or more and otherwise falls back to a fixed 0.1 µm: with fewer points
  // in all, the "estimate" would be that constant, printed as if measured (issue 18: one point gave "noise 0.10 µm
  // (estimated)").
  constexpr std::size_t kMinPointsToEstimateNoise = 10;
  if (noise_um <= 0.0 && pts.size() < kMinPointsToEstimateNoise)
    throw std::invalid_argument(fmt::format("compare: estimating the probe noise needs at least {} measured points, the "
                                            "measurement has {}: give the noise (--noise-um)",
                                            kMinPointsToEstimateNoise, pts.size()));
  Comparison c;
  check();
  c.model_um = predict(setup, model, pts, grinding::Method::Exact, 0, keep_going);
  check();
  c.allowance_offset_um = mean_allowance_offset_um(setup.geometry());
  c.residual_um.resize(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) c.residual_um[i] = pts[i].deviation_um - c.model_um[i];
  c.noise_estimated = noise_um <= 0.0;
  c.flanks = flank_residuals(setup.ranges(), pts, c.residual_um, &c.flank_point_index, &c.flank_duplicates);
  c.noise_um = noise_um;
  check();
  if (c.noise_estimated) {
    // As estimate_noise_um (diagnose uses the same σ), saying which way it was found.
    const LineNoise lines = line_noise_um(c.flanks);
    c.noise_um = lines.lines > 0 ? std::max(lines.sigma_um, kNoiseFloorUm) : estimate_noise_um(pts, c.residual_um);
    c.noise_source = lines.lines > 0
                         ? fmt::format("estimated from the point-to-point scatter along {} measured lines", lines.lines)
                         : std::string("estimated from a quadratic surface per flank");
  }

  PatternOptions po;
  po.noise_um = c.noise_um;
  RegionOptions ro;
  ro.noise_um = c.noise_um;
  // A lone point beyond 3σ is what noise gives 0.27 % of the points (0.7 of the 252 of two measured teeth): listed
  // beside a whole-flank region it read as a finding (issue 17). Regions need two points here.
  ro.min_points = 2;
  // Each flank's patterns and regions on their own (both cores; every flank writes its own slot, so the result does
  // not depend on the thread count), then gathered in flank order.
  const auto nf = c.flanks.size();
  c.patterns.assign(nf, FlankPatterns{});
  std::vector<char> fitted(nf, 0);
  std::vector<std::vector<FailingRegion>> flank_regions(nf);
  parallel_for(static_cast<int>(nf), 0, [&](int k) {
    check(); // parallel_for stops at the first exception
    const auto& f = c.flanks[static_cast<std::size_t>(k)];
    try {
      c.patterns[static_cast<std::size_t>(k)] = fit_flank_patterns(f, po);
      fitted[static_cast<std::size_t>(k)] = 1;
    } catch (const std::invalid_argument&) { // too few distinct positions on this flank for the six patterns
    }
    flank_regions[static_cast<std::size_t>(k)] = find_failing_regions(f, ro);
  });
  std::map<int, std::vector<FlankPatterns>> by_side;
  for (std::size_t k = 0; k < nf; ++k) {
    c.has_patterns.push_back(fitted[k] != 0);
    if (fitted[k]) by_side[static_cast<int>(c.flanks[k].side)].push_back(c.patterns[k]);
    for (auto& reg : flank_regions[k]) c.regions.push_back(std::move(reg));
  }
  for (const auto& [side, list] : by_side)
    if (list.size() >= 2) c.trends.push_back(fit_tooth_trends(list, setup.geometry().teeth()));
  check();
  c.summary = summarize_residuals(c.flanks);
  c.reference_in_doubt = reference_in_doubt(setup.geometry(), pts, c.residual_um, c.noise_um);
  check();
  if (pts.size() >= 4) c.follows = residual_dependence(setup, pts, c.residual_um);
  check();
  for (const auto& f : c.flanks) {
    const auto crossings = line_crossings(f);
    if (crossings.empty()) continue;
    LineAgreement a;
    a.tooth = f.tooth;
    a.side = f.side;
    a.crossings = crossings.size();
    for (const auto& x : crossings) {
      const double d = x.profile_um - x.helix_um;
      a.mean_difference_um += d / static_cast<double>(crossings.size());
      a.max_abs_difference_um = std::max(a.max_abs_difference_um, std::abs(d));
    }
    // Two independent noisy values differ by σ√2 RMS; linear interpolation on dense lines adds little.
    a.disagree = a.max_abs_difference_um > std::max(4.0 * std::sqrt(2.0) * c.noise_um, 0.1);
    if (a.disagree)
      a.sentence = fmt::format("tooth {}, {} flank: its profile and helix lines disagree where they cross (profile − helix "
                               "{:+.2f} µm on average, up to {:.2f} µm at {} crossings): they cannot both be right — "
                               "check the export's sign convention and direction (--mka-signs, --mka-direction) or a "
                               "probe re-registration between the lines",
                               f.tooth, to_string(f.side), a.mean_difference_um, a.max_abs_difference_um, a.crossings);
    c.line_agreement.push_back(std::move(a));
  }
  // Patterns and regions of a flank whose lines disagree are made by that disagreement as much as by the gear (an
  // export's helix lines read with the wrong sign show as a 5 µm "waviness along the profile"): each says so.
  c.disputed_sign.assign(nf, false);
  for (std::size_t k = 0; k < nf; ++k)
    for (const auto& a : c.line_agreement)
      if (a.disagree && a.tooth == c.flanks[k].tooth && a.side == c.flanks[k].side) c.disputed_sign[k] = true;
  for (auto& reg : c.regions)
    for (std::size_t k = 0; k < nf; ++k)
      if (c.disputed_sign[k] && reg.tooth == c.flanks[k].tooth && reg.side == c.flanks[k].side)
        reg.sentence += kDisputedSignNote;
  c.counts.read = pts.size();
  c.counts.used = c.summary.overall.points;
  for (const auto& f : c.summary.flanks) c.counts.outside_evaluation_range += f.points_outside_range;
  for (const auto n : c.flank_duplicates) c.counts.duplicates += n;
  c.counts.undefined_values = read.undefined_values;
  c.counts.off_flank_points = read.off_flank_points;
  if (c.counts.used + c.counts.outside_evaluation_range + c.counts.duplicates != c.counts.read) // a broken invariant
    throw std::logic_error(fmt::format("compare: {} points read but {} used + {} outside + {} duplicates", c.counts.read,
                                       c.counts.used, c.counts.outside_evaluation_range, c.counts.duplicates));
  return c;
}

std::string describe_point_counts(const PointCounts& c) {
  const auto plural = [](std::size_t n, const char* one, const char* many) { return fmt::format("{} {}", n, n == 1 ? one : many); };
  return fmt::format("{} read: {} used (inside the evaluation ranges), {} outside the evaluation ranges, {}; left out by "
                     "the reader: {}, {}",
                     plural(c.read, "measured point", "measured points"), c.used, c.outside_evaluation_range,
                     plural(c.duplicates, "duplicate position", "duplicate positions"),
                     plural(c.undefined_values, "undefined value", "undefined values"),
                     plural(c.off_flank_points, "point off the flank", "points off the flank"));
}

std::vector<FlankResiduals> flank_residuals(const gears::EvaluationRanges& r, const std::vector<MeasuredPoint>& pts,
                                            const std::vector<double>& residual_um,
                                            std::vector<std::vector<size_t>>* point_index,
                                            std::vector<std::size_t>* duplicates) {
  std::map<std::pair<int, int>, size_t> index;
  std::vector<FlankResiduals> flanks;
  std::vector<std::vector<size_t>> members;
  std::vector<std::size_t> repeated;
  // Positions seen per flank, on a 1 nm lattice: a grid's and a trace's points are far apart; the same point twice
  // (an export listing a line twice, a profile and a helix trace sharing a node) would count twice in every statistic.
  std::vector<std::set<std::pair<long long, long long>>> seen;
  const auto nm = [](double mm) { return std::llround(mm * 1e6); };
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
      repeated.push_back(0);
      seen.emplace_back();
    }
    if (!seen[it->second].insert({nm(pts[i].roll_length_mm), nm(pts[i].z_mm)}).second) {
      ++repeated[it->second];
      continue;
    }
    flanks[it->second].points.push_back({pts[i].roll_length_mm, pts[i].z_mm, residual_um[i]});
    members[it->second].push_back(i);
  }
  // Order flanks by tooth, then left before right (the map's order).
  std::vector<FlankResiduals> ordered;
  std::vector<std::vector<size_t>> ordered_index;
  std::vector<std::size_t> ordered_repeated;
  for (const auto& [key, k] : index) {
    ordered.push_back(std::move(flanks[k]));
    ordered_index.push_back(std::move(members[k]));
    ordered_repeated.push_back(repeated[k]);
  }
  if (point_index) *point_index = std::move(ordered_index);
  if (duplicates) *duplicates = std::move(ordered_repeated);
  return ordered;
}

} // namespace geartopo::diagnosis
