// geartopo diagnosis — which effect is missing (diagnose.hpp): the pipeline of stages (pipeline/stages.hpp), the
// candidates' names and the noise estimate. Units: µm.
#include "geartopo/diagnosis/diagnose.hpp"

#include "diagnosis_dump.hpp"
#include "pipeline/stages.hpp"

#include "geartopo/diagnosis/residuals/line_noise.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>

namespace geartopo::diagnosis {

std::string Candidate::name() const {
  std::string s = label;
  for (const auto& e : effects) s += (s.empty() ? "" : " + ") + e.type;
  for (const auto& c : changes)
    s += fmt::format("{}{} {}", s.empty() ? "" : " + ", machine::info(chain, c.component).name, c.law_name());
  return wheel_flank ? fmt::format("{} ({})", s, to_string(*wheel_flank)) : s;
}

bool Candidate::nested_in(const Candidate& bigger) const {
  if (effects.size() >= bigger.effects.size()) return false;
  return std::all_of(effects.begin(), effects.end(), [&](const scene::EffectSpec& e) {
    return std::any_of(bigger.effects.begin(), bigger.effects.end(),
                       [&](const scene::EffectSpec& f) { return f.type == e.type; });
  });
}

int Candidate::fitted_parameters() const {
  int p = 0;
  for (const auto& params : parameters)
    for (const auto& q : params) p += q.fitted ? 1 : 0;
  return p;
}

double estimate_noise_um(const std::vector<MeasuredPoint>& pts, const std::vector<double>& r) {
  // Measured traces: σ from the lines' own point-to-point scatter (line_noise.hpp). A surface fitted across lines
  // would take their disagreement and every pattern the surface lacks for noise (issue 28: 1.23 µm on noise-free data).
  std::map<std::pair<int, int>, FlankResiduals> by_flank;
  for (size_t i = 0; i < pts.size(); ++i)
    by_flank[{pts[i].tooth, static_cast<int>(pts[i].flank)}].points.push_back({pts[i].roll_length_mm, pts[i].z_mm, r[i]});
  std::vector<FlankResiduals> flanks;
  for (auto& [key, f] : by_flank) flanks.push_back(std::move(f));
  if (const LineNoise lines = line_noise_um(flanks); lines.lines > 0) return std::max(lines.sigma_um, kNoiseFloorUm);
  double rss = 0.0, dof = 0.0;
  for (const auto& f : stages::flank_surfaces(pts)) {
    Eigen::VectorXd y(static_cast<long>(f.idx.size()));
    for (size_t k = 0; k < f.idx.size(); ++k) y(static_cast<long>(k)) = r[f.idx[k]];
    const Eigen::VectorXd beta = f.X.colPivHouseholderQr().solve(y);
    rss += (y - f.X * beta).squaredNorm();
    dof += static_cast<double>(f.idx.size()) - 6.0;
  }
  constexpr double kFallbackNoiseUm = 0.1;
  return dof > 0.0 && rss > 0.0 ? std::sqrt(rss / dof) : kFallbackNoiseUm;
}

// The stages in order (docs/diagnosis.md, "The pipeline"): each reads the context and the earlier results and returns
// its own; the Diagnosis and its verdict are composed from all of them at the end.
Diagnosis diagnose(const grinding::GrindingSetup& setup, const grinding::GrindingProcess& model,
                   const std::vector<MeasuredPoint>& points, const std::vector<std::string>& in_scene,
                   const DiagnoseOptions& options) {
  const auto keep_going = [&options] { if (options.keep_going) options.keep_going(); };
  const stages::Context ctx(setup, model, points, in_scene, options);
  keep_going();
  std::optional<Decision> reference = stages::reference_in_doubt(ctx);
  stages::FitProgress progress{options};
  const stages::LibraryFits library = stages::fit_library(ctx, progress);
  const stages::PairFits pairs = stages::fit_pairs(ctx, library, progress);
  keep_going();
  const stages::LibraryJudgement judgement = stages::judge_library(ctx, library, pairs);
  const stages::BeyondLibrary beyond = stages::try_families(ctx, judgement);
  keep_going();
  const stages::Alternatives alternatives = stages::find_alternatives(ctx, library, pairs, judgement, beyond);
  keep_going();
  const std::optional<Candidate>& chosen = beyond.outcome == stages::BeyondLibrary::Outcome::named
                                               ? beyond.best
                                               : judgement.pick;
  stages::Plans plans = stages::make_plans(ctx, chosen, alternatives);
  keep_going();
  auto draws = stages::posterior_draws(ctx, chosen);
  Diagnosis d = stages::compose(ctx, std::move(reference), library, pairs, judgement, beyond, alternatives, std::move(plans), std::move(draws));
  dump_if_asked(d);
  return d;
}

} // namespace geartopo::diagnosis
