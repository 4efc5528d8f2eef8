// geartopo diagnosis — what to measure next when two explanations fit equally well (docs/diagnosis.md, "Ambiguity and
// what to measure next"). Both explanations were fitted to the same measured points, so they agree there; where they
// part is on the teeth not measured (ground at other times, at other angles). Each explanation's prediction at a
// point is its effects' first-order deviation plus its own set-up terms (thickness, rotation: refitted on the
// measured points with those effects); the difference Δ (µm) over a tooth's grid, in units of the noise σ, is how far
// a measurement of that tooth would move the two apart: √(Σ Δ²)/σ, whose square is the χ² it adds. Units: µm, mm.
#include "geartopo/diagnosis/diagnose.hpp"

#include "setup_terms.hpp"

#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace geartopo::diagnosis {
namespace {

/// The first-order deviation (µm) of a candidate's effects at the points; zero for "no effect" (no effects).
std::vector<double> effects_at(const grinding::GrindingSetup& setup, const Candidate& c,
                               const std::vector<MeasuredPoint>& pts, int threads) {
  if (c.effects.empty()) return std::vector<double>(pts.size(), 0.0);
  const auto effs = workbench::make_effects(c.effects, setup);
  const grinding::IdealProcess ideal;
  const effects::EffectsProcess process(ideal, effs);
  return predict(setup, process, pts, grinding::Method::Linear, threads);
}

/// The set-up terms that go with a candidate on the measured points: fitted to residual − its effects.
SetupTerms setup_terms_of(const SetupTermModel& model, const std::vector<double>& residual,
                          const std::vector<double>& effects) {
  Eigen::VectorXd r(static_cast<Eigen::Index>(residual.size()));
  for (size_t i = 0; i < residual.size(); ++i) r(static_cast<Eigen::Index>(i)) = residual[i] - effects[i];
  return model.fit(r, 1.0);
}

} // namespace

MeasurementPlan plan_measurement(const grinding::GrindingSetup& setup, const std::vector<MeasuredPoint>& pts,
                                 const std::vector<double>& residual, const Candidate& a, const Candidate& b,
                                 double noise_um, const DiagnoseOptions& o) {
  MeasurementPlan plan;
  plan.first = a.effects.empty() ? "none" : a.name();
  plan.second = b.effects.empty() ? "none" : b.name();
  plan.delta_bic_gap = b.delta_bic - a.delta_bic;
  plan.noise_um = noise_um;
  plan.rows = o.plan_rows;
  plan.cols = o.plan_cols;

  // Set-up terms of each explanation, from the measured points.
  const SetupTermModel model(setup.geometry(), pts);
  const SetupTerms sa = setup_terms_of(model, residual, effects_at(setup, a, pts, o.threads));
  const SetupTerms sb = setup_terms_of(model, residual, effects_at(setup, b, pts, o.threads));

  // The grid of every unmeasured tooth, both flanks (rows from root to tip, columns along the face width).
  std::set<int> measured;
  for (const auto& p : pts) measured.insert(p.tooth);
  const auto& g = setup.geometry();
  const auto rolls = grinding::grid_roll_lengths(setup.ranges(), o.plan_rows);
  const auto zs = grinding::grid_axial_positions(setup.ranges(), o.plan_cols);
  std::vector<MeasuredPoint> grid;
  for (int tooth = 1; tooth <= g.teeth(); ++tooth) {
    if (measured.count(tooth)) continue;
    for (Flank flank : {Flank::Left, Flank::Right})
      for (int row = 0; row < o.plan_rows; ++row)
        for (int col = 0; col < o.plan_cols; ++col) {
          MeasuredPoint p;
          p.tooth = tooth;
          p.flank = flank;
          p.row = row + 1;
          p.col = col + 1;
          p.roll_length_mm = rolls[static_cast<size_t>(row)];
          p.diameter_mm = g.diameter_at_roll_length(p.roll_length_mm);
          p.z_mm = zs[static_cast<size_t>(col)];
          grid.push_back(p);
        }
  }
  if (grid.empty()) return plan; // every tooth measured: nothing left to suggest

  const auto ea = effects_at(setup, a, grid, o.threads), eb = effects_at(setup, b, grid, o.threads);
  // µm of normal offset per µrad of turn (setup_terms.hpp): r_b (mm) · cos β_b · 1e-3.
  const double um_per_urad = 0.5 * g.base_diameter_mm() * std::cos(g.base_helix_angle()) * 1e-3;
  plan.row_separation_sigma.assign(static_cast<size_t>(o.plan_rows), 0.0);
  plan.col_separation_sigma.assign(static_cast<size_t>(o.plan_cols), 0.0);
  const double s2 = noise_um * noise_um;
  for (size_t i = 0; i < grid.size();) {
    ToothSuggestion t;
    t.tooth = grid[i].tooth;
    double chi2 = 0.0;
    for (; i < grid.size() && grid[i].tooth == t.tooth; ++i) {
      const auto& p = grid[i];
      const double side = side_sign(p.flank) * um_per_urad;
      const double pa = ea[i] + sa.thickness_um + side * sa.rotation_urad;
      const double pb = eb[i] + sb.thickness_um + side * sb.rotation_urad;
      const double d = pa - pb;
      chi2 += d * d / s2;
      plan.row_separation_sigma[static_cast<size_t>(p.row - 1)] += d * d / s2;
      plan.col_separation_sigma[static_cast<size_t>(p.col - 1)] += d * d / s2;
      if (std::abs(d) > t.max_difference_um) t.max_difference_um = std::abs(d), t.flank = p.flank, t.row = p.row, t.col = p.col;
    }
    t.separation_sigma = std::sqrt(chi2);
    plan.teeth.push_back(t);
  }
  for (auto& v : plan.row_separation_sigma) v = std::sqrt(v);
  for (auto& v : plan.col_separation_sigma) v = std::sqrt(v);
  std::stable_sort(plan.teeth.begin(), plan.teeth.end(), [](const ToothSuggestion& x, const ToothSuggestion& y) {
    return x.separation_sigma > y.separation_sigma;
  });
  double chi2 = 0.0;
  for (const auto& t : plan.teeth) {
    if (std::sqrt(chi2) >= o.plan_target_sigma) break;
    plan.recommended_teeth.push_back(t.tooth);
    chi2 += t.separation_sigma * t.separation_sigma;
  }
  plan.recommended_separation_sigma = std::sqrt(chi2);
  return plan;
}

} // namespace geartopo::diagnosis
