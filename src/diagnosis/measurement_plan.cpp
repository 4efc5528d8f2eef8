// geartopo diagnosis — what to measure next when two explanations fit equally well (docs/diagnosis.md, "Ambiguity and
// what to measure next"). Both explanations were fitted to the same measured points, so they agree there; where they
// part is on the teeth not measured (ground at other times, at other angles). Each explanation's prediction at a
// point is its effects' first-order deviation plus its own set-up terms (thickness, rotation: refitted on the
// measured points with those effects); the difference Δ (µm) over a tooth's grid, in units of the noise σ, ranks the
// teeth: √(Σ Δ²)/σ. That raw difference over-promises — once the new teeth are measured both explanations are refitted
// on all points and absorb part of it — so the recommendation is scored after the refit: for a few options (the best
// teeth, on the plan grid and denser ones) the new points are synthesised from one explanation without noise, the
// other is refitted on measured + new points, and the expected ΔBIC gap is what "resolves" is judged on. Units: µm, mm.
#include "geartopo/diagnosis/diagnose.hpp"

#include "effect_fit.hpp"
#include "setup_terms.hpp"

#include "geartopo/diagnosis/effect_contribution.hpp"
#include "geartopo/diagnosis/hypothesis_family.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/grinding/topology.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

namespace geartopo::diagnosis {
namespace {

/// A hypothesis' columns at the points (n × p): its family's, at the points' contact states.
Eigen::MatrixXd columns_at(const grinding::GrindingSetup& setup, const Candidate& c, const std::vector<MeasuredPoint>& pts,
                           const DiagnoseOptions& o) {
  const EffectContribution at(setup, pts, o.threads, o.chain, o.datum_face_z_mm);
  return c.family->columns(c, ContactStates(setup, at, nullptr, o.threads));
}

/// The first-order deviation (µm) of a candidate's effects at the points; zero for "no effect" (no effects). A
/// hypothesis beyond the library by its linear field X β at the points' generating poses: the same columns it was
/// fitted with (hypothesis_family.hpp).
std::vector<double> effects_at(const grinding::GrindingSetup& setup, const Candidate& c,
                               const std::vector<MeasuredPoint>& pts, const DiagnoseOptions& o) {
  const int threads = o.threads;
  if (c.family) {
    const Eigen::VectorXd field = columns_at(setup, c, pts, o) * c.coefficients;
    return {field.data(), field.data() + field.size()};
  }
  if (c.effects.empty()) return std::vector<double>(pts.size(), 0.0);
  const auto effs = workbench::make_effects(c.effects, setup);
  const grinding::IdealProcess ideal;
  const effects::EffectsProcess process(ideal, effs, o.chain, o.datum_face_z_mm);
  return predict(setup, process, pts, grinding::Method::Linear, threads);
}

/// The set-up terms that go with a candidate on the measured points: fitted to residual − its effects.
SetupTerms setup_terms_of(const SetupTermModel& model, const std::vector<double>& residual,
                          const std::vector<double>& effects) {
  Eigen::VectorXd r(static_cast<Eigen::Index>(residual.size()));
  for (size_t i = 0; i < residual.size(); ++i) r(static_cast<Eigen::Index>(i)) = residual[i] - effects[i];
  return model.fit(r, 1.0);
}

/// The points of a grid (rows × cols per flank, ISO evaluation ranges, rows from root to tip, columns along the face
/// width) on both flanks of each tooth, tooth by tooth.
std::vector<MeasuredPoint> grid_points(const grinding::GrindingSetup& setup, const std::vector<int>& teeth, int rows,
                                       int cols) {
  const auto& g = setup.geometry();
  const auto rolls = grinding::grid_roll_lengths(setup.ranges(), rows);
  const auto zs = grinding::grid_axial_positions(setup.ranges(), cols);
  std::vector<MeasuredPoint> grid;
  for (int tooth : teeth)
    for (Flank flank : {Flank::Left, Flank::Right})
      for (int row = 0; row < rows; ++row)
        for (int col = 0; col < cols; ++col) {
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
  return grid;
}

/// The points of traces on both flanks of each tooth, tooth by tooth, as a measuring machine takes them: a profile
/// trace (points_per_trace roll lengths over the ISO profile evaluation range) at each face-width position z (mm) and a
/// helix trace (points_per_trace positions over the helix evaluation range) at each roll length (mm). No grid indices.
std::vector<MeasuredPoint> trace_points(const grinding::GrindingSetup& setup, const std::vector<int>& teeth,
                                        const std::vector<double>& profile_z_mm, const std::vector<double>& helix_roll_mm,
                                        int points_per_trace) {
  const auto& g = setup.geometry();
  const auto rolls = grinding::grid_roll_lengths(setup.ranges(), points_per_trace);
  const auto zs = grinding::grid_axial_positions(setup.ranges(), points_per_trace);
  std::vector<MeasuredPoint> out;
  const auto add = [&](int tooth, Flank flank, double roll, double z) {
    MeasuredPoint p;
    p.tooth = tooth, p.flank = flank, p.roll_length_mm = roll, p.z_mm = z;
    p.diameter_mm = g.diameter_at_roll_length(roll);
    out.push_back(p);
  };
  for (int tooth : teeth)
    for (Flank flank : {Flank::Left, Flank::Right}) {
      for (double z : profile_z_mm)
        for (double roll : rolls) add(tooth, flank, roll, z);
      for (double roll : helix_roll_mm)
        for (double z : zs) add(tooth, flank, roll, z);
    }
  return out;
}

/// One explanation as fitted on the measured points: its effects at them and its set-up terms.
struct Fitted {
  const Candidate* candidate = nullptr;
  std::vector<double> effects_measured; ///< first-order deviation of its effects at the measured points (µm)
  SetupTerms terms;
  double rss = 0.0;                     ///< Σ r² left on the measured points, set-up terms removed (µm²)
  Eigen::MatrixXd columns_measured;     ///< a machine hypothesis: its columns at the measured points (n × p), else empty
};

/// Its prediction (µm) at new points: effects plus set-up terms (t + σ_i r_b cos β_b ψ).
std::vector<double> prediction_at(const grinding::GrindingSetup& setup, const Fitted& f,
                                  const std::vector<MeasuredPoint>& grid, const DiagnoseOptions& o) {
  auto e = effects_at(setup, *f.candidate, grid, o);
  for (size_t i = 0; i < grid.size(); ++i) e[i] += setup_offset_um(setup.geometry(), grid[i].flank, f.terms);
  return e;
}

/// Expected ΔBIC(loser) − ΔBIC(truth) after measuring `grid` (unit-free): the new points take the truth's prediction
/// without noise; the truth at its fitted values then leaves exactly its RSS on the measured points (refitting it can
/// not do better: that is its minimum there, and it fits the new points exactly), the loser is refitted on measured +
/// new (warm-started from its values); both are charged the expected noise σ² per new point.
double expected_gap(const grinding::GrindingSetup& setup, const std::vector<MeasuredPoint>& pts,
                    const std::vector<double>& residual, const Fitted& truth, const Fitted& loser,
                    const std::vector<MeasuredPoint>& grid, const std::vector<double>& truth_at_grid, double noise_um,
                    const DiagnoseOptions& o) {
  std::vector<MeasuredPoint> all = pts;
  all.insert(all.end(), grid.begin(), grid.end());
  std::vector<double> r = residual;
  r.insert(r.end(), truth_at_grid.begin(), truth_at_grid.end());
  const SetupTermModel terms(setup.geometry(), all);
  const double n = static_cast<double>(all.size());
  double loser_rss = 0.0;
  if (loser.candidate->family) {
    // Linear in its coefficients: least squares on its columns at measured + new points, set-up terms removed.
    const Eigen::MatrixXd& Xm = loser.columns_measured;
    const Eigen::MatrixXd Xn = columns_at(setup, *loser.candidate, grid, o); // grid × p
    Eigen::MatrixXd X(Xm.rows() + Xn.rows(), Xm.cols());
    X << Xm, Xn;
    Eigen::MatrixXd Xp(X.rows(), X.cols());
    for (Eigen::Index j = 0; j < X.cols(); ++j) Xp.col(j) = terms.remove(Eigen::VectorXd(X.col(j)));
    const Eigen::VectorXd y = terms.remove(Eigen::Map<const Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size())));
    const Eigen::VectorXd beta = Xp.colPivHouseholderQr().solve(y);
    loser_rss = (y - Xp * beta).squaredNorm();
  } else if (loser.candidate->effects.empty()) {
    loser_rss = terms.remove(Eigen::Map<const Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size()))).squaredNorm();
  } else {
    std::vector<std::string> types;
    std::map<std::string, std::vector<double>> warm;
    for (const auto& e : loser.candidate->effects) types.push_back(e.type), warm[e.type] = e.values;
    DiagnoseOptions quick = o;
    quick.profile_walk_steps = 0; // only the RSS is wanted, not the uncertainties
    const EffectContribution at_all(setup, all, o.threads, o.chain, o.datum_face_z_mm); // contact states, once per refit
    const Candidate refit = fit_effects(setup, at_all, r, types, warm, terms, quick);
    loser_rss = refit.rms_after_um * refit.rms_after_um * n;
  }
  const double new_noise = static_cast<double>(grid.size()) * noise_um * noise_um;
  return n * std::log((loser_rss + new_noise) / std::max(truth.rss + new_noise, 1e-300)) +
         static_cast<double>(loser.candidate->fitted_parameters() - truth.candidate->fitted_parameters()) * std::log(n);
}

/// Raw difference per tooth, row and column: where the two explanations part on the grid of every unmeasured tooth
/// (pa, pb: their predictions there), before any refit; the teeth largest separation first.
void separate_on_teeth(MeasurementPlan& plan, const std::vector<MeasuredPoint>& grid, const std::vector<double>& pa,
                       const std::vector<double>& pb, double noise_um, const DiagnoseOptions& o) {
  plan.row_separation_sigma.assign(static_cast<size_t>(o.plan_rows), 0.0);
  plan.col_separation_sigma.assign(static_cast<size_t>(o.plan_cols), 0.0);
  const double s2 = noise_um * noise_um;
  for (size_t i = 0; i < grid.size();) {
    ToothSuggestion t;
    t.tooth = grid[i].tooth;
    double chi2 = 0.0;
    for (; i < grid.size() && grid[i].tooth == t.tooth; ++i) {
      const auto& p = grid[i];
      const double d = pa[i] - pb[i];
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
}

/// The measurement options scored after refit, fewest new points first, until one resolves; the recommendation.
void score_options(MeasurementPlan& plan, const grinding::GrindingSetup& setup, const std::vector<MeasuredPoint>& pts,
                   const std::vector<double>& residual, const Fitted& fa, const Fitted& fb, double noise_um,
                   const DiagnoseOptions& o) {
  const Candidate& a = *fa.candidate;
  const Candidate& b = *fb.candidate;
  const double s2 = noise_um * noise_um;
  // Options: the best k teeth (k = 2, 4, 8, 16, at most all) on the plan grid and on grids 2× and 3× denser each
  // way, fewest new points first (then fewest teeth). Scored after refit until one resolves: both expected gaps reach
  // the target. A few joint fits each; the denser ones only when the cheaper ones do not suffice.
  // Traces: m × the profile and helix lines per flank instead of an m×-denser grid.
  const bool traces = o.plan_layout == DiagnoseOptions::PlanLayout::Traces;
  const int lines = o.plan_profile_traces + o.plan_helix_traces;
  std::vector<std::tuple<int, int, int>> shapes; // (points, teeth, density)
  for (int k : {2, 4, 8, 16}) {
    const int teeth = std::min<int>(k, static_cast<int>(plan.teeth.size()));
    for (int m : {1, 2, 3}) {
      const int per_flank = traces ? m * lines * o.plan_trace_points : m * o.plan_rows * m * o.plan_cols;
      const auto shape = std::make_tuple(teeth * 2 * per_flank, teeth, m);
      if (std::find(shapes.begin(), shapes.end(), shape) == shapes.end()) shapes.push_back(shape);
    }
  }
  std::sort(shapes.begin(), shapes.end());
  double best_worst_gap = -1e300;
  for (const auto& [points, k, m] : shapes) {
    MeasurementOption opt;
    for (int j = 0; j < k; ++j) opt.teeth.push_back(plan.teeth[static_cast<size_t>(j)].tooth);
    opt.points = points;
    std::vector<MeasuredPoint> new_points;
    if (traces) {
      opt.traces = true;
      opt.points_per_trace = o.plan_trace_points;
      opt.profile_z_mm = grinding::grid_axial_positions(setup.ranges(), m * o.plan_profile_traces);
      const auto helix_rolls = grinding::grid_roll_lengths(setup.ranges(), m * o.plan_helix_traces);
      for (double roll : helix_rolls) opt.helix_diameter_mm.push_back(setup.geometry().diameter_at_roll_length(roll));
      new_points = trace_points(setup, opt.teeth, opt.profile_z_mm, helix_rolls, o.plan_trace_points);
    } else {
      opt.rows = m * o.plan_rows;
      opt.cols = m * o.plan_cols;
      new_points = grid_points(setup, opt.teeth, opt.rows, opt.cols);
    }
    const auto a_new = prediction_at(setup, fa, new_points, o), b_new = prediction_at(setup, fb, new_points, o);
    double chi2 = 0.0;
    for (size_t i = 0; i < new_points.size(); ++i) chi2 += (a_new[i] - b_new[i]) * (a_new[i] - b_new[i]) / s2;
    opt.separation_before_refit_sigma = std::sqrt(chi2);
    opt.delta_bic_if_first = expected_gap(setup, pts, residual, fa, fb, new_points, a_new, noise_um, o);
    opt.delta_bic_if_second = expected_gap(setup, pts, residual, fb, fa, new_points, b_new, noise_um, o);
    // A direction whose truth is nested in the other explanation (eccentricity inside eccentricity + wear) cannot
    // reach the target: the larger one refits the smaller one's data exactly and falls behind only by its extra
    // parameters' penalty, Δp ln N. It needs no more: a nested rival that is not the better fit is no rival (diagnose,
    // "Ambiguity"). That direction is then judged by the other one alone.
    const double if_first = a.nested_in(b) ? o.plan_target_delta_bic : opt.delta_bic_if_first;
    const double if_second = b.nested_in(a) ? o.plan_target_delta_bic : opt.delta_bic_if_second;
    const double worst = std::min(if_first, if_second);
    opt.resolves = worst >= o.plan_target_delta_bic;
    plan.options.push_back(opt);
    if (opt.resolves || worst > best_worst_gap) best_worst_gap = worst, plan.recommended = opt;
    if (opt.resolves) break;
  }
}

} // namespace

std::string what_to_measure(const MeasurementOption& m) {
  if (!m.traces) return fmt::format("a {} × {} grid per flank", m.rows, m.cols);
  return fmt::format("{} profile traces (z = {:.1f} mm) and {} helix traces (d = {:.1f} mm) of {} points per flank",
                     m.profile_z_mm.size(), fmt::join(m.profile_z_mm, ", "), m.helix_diameter_mm.size(),
                     fmt::join(m.helix_diameter_mm, ", "), m.points_per_trace);
}

MeasurementPlan plan_measurement(const grinding::GrindingSetup& setup, const std::vector<MeasuredPoint>& pts,
                                 const std::vector<double>& residual, const Candidate& a, const Candidate& b,
                                 double noise_um, const DiagnoseOptions& o) {
  MeasurementPlan plan;
  plan.first = a.effects.empty() && a.changes.empty() ? "none" : a.name();
  plan.second = b.effects.empty() && b.changes.empty() ? "none" : b.name();
  plan.delta_bic_gap = b.delta_bic - a.delta_bic;
  plan.noise_um = noise_um;
  plan.rows = o.plan_rows;
  plan.cols = o.plan_cols;

  // The unmeasured teeth: where the two explanations can part (none: nothing to suggest).
  std::set<int> measured;
  for (const auto& p : pts) measured.insert(p.tooth);
  std::vector<int> unmeasured;
  for (int tooth = 1; tooth <= setup.geometry().teeth(); ++tooth)
    if (!measured.count(tooth)) unmeasured.push_back(tooth);
  if (unmeasured.empty()) return plan;

  // Each explanation on the measured points: its effects, its set-up terms and the RSS it leaves.
  const SetupTermModel model(setup.geometry(), pts);
  const auto fitted = [&](const Candidate& c) {
    Fitted f;
    f.candidate = &c;
    if (c.family) {
      f.columns_measured = columns_at(setup, c, pts, o);
      const Eigen::VectorXd e = f.columns_measured * c.coefficients;
      f.effects_measured.assign(e.data(), e.data() + e.size());
    } else {
      f.effects_measured = effects_at(setup, c, pts, o);
    }
    f.terms = setup_terms_of(model, residual, f.effects_measured);
    Eigen::VectorXd r(static_cast<Eigen::Index>(pts.size()));
    for (size_t i = 0; i < pts.size(); ++i) r(static_cast<Eigen::Index>(i)) = residual[i] - f.effects_measured[i];
    f.rss = model.remove(r).squaredNorm();
    return f;
  };
  const Fitted fa = fitted(a), fb = fitted(b);

  // The grid of every unmeasured tooth, both flanks.
  const auto grid = grid_points(setup, unmeasured, o.plan_rows, o.plan_cols);

  const auto pa = prediction_at(setup, fa, grid, o), pb = prediction_at(setup, fb, grid, o);
  separate_on_teeth(plan, grid, pa, pb, noise_um, o);
  score_options(plan, setup, pts, residual, fa, fb, noise_um, o);
  return plan;
}

} // namespace geartopo::diagnosis
