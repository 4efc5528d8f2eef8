// geartopo diagnosis — every family's hypotheses fitted to the residual (stages.hpp, fit_hypotheses). Each hypothesis
// is linear in its coefficients, so its fit is a least-squares projection of the residual, with the set-up terms
// removed, onto its columns at the points' stored contact states: hundreds of hypotheses in a fraction of a second on
// 10⁵ points. Units: µm; coefficients in their columns' units.
#include "../pipeline/stages.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

namespace geartopo::diagnosis::stages {
namespace {

/// The least-squares fit of the judged columns Xp (n × p) to y (n), or none when a direction is one the set-up terms
/// already hold (a constant Z change is a turn of the helicoid): it explains nothing new.
std::optional<LinearFit> least_squares(const Eigen::MatrixXd& Xp, const Eigen::VectorXd& y, double setup_count) {
  const auto n = static_cast<double>(y.size()), p = static_cast<double>(Xp.cols());
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Xp);
  if (qr.rank() < Xp.cols() || Xp.norm() == 0.0) return std::nullopt;
  LinearFit f;
  f.beta = qr.solve(y);
  f.rss = (y - Xp * f.beta).squaredNorm();
  const double sigma2 = f.rss / std::max(1.0, n - setup_count - p);
  f.cov = sigma2 * (Xp.transpose() * Xp).inverse();
  if (!(f.beta.allFinite() && f.cov.allFinite())) return std::nullopt;
  return f;
}

/// One hypothesis fitted with its family's finding and the scores every hypothesis shares; none when it is invisible on
/// these flanks (its largest plausible size moves the judged data by less than 1e-4 µm RMS: a roll of the wheel spindle
/// about its own axis turns a surface of revolution into itself, and its fit would be numerical noise with a huge
/// value) or explains nothing the set-up terms do not.
std::optional<Candidate> fitted(const Context& ctx, const ContactStates& states, const HypothesisFamily& family,
                                const std::shared_ptr<const HypothesisFamily>& owner, Candidate h, const Eigen::VectorXd& y,
                                double rss0) {
  const Eigen::MatrixXd X = family.columns(h, states); // n × p
  if (X.isZero(0.0)) return std::nullopt;
  const Eigen::MatrixXd Xp = states.judged(X);
  const Eigen::VectorXd size = family.plausible_size(h, states, ctx.options);
  double largest = 0.0;
  for (Eigen::Index j = 0; j < Xp.cols(); ++j) largest = std::max(largest, Xp.col(j).norm() * size(j) / std::sqrt(ctx.n));
  if (largest < 1e-4) return std::nullopt;
  const auto f = least_squares(Xp, y, ctx.setup_terms.count());
  if (!f) return std::nullopt;
  Candidate c = family.finding(std::move(h), *f, states, ctx.options);
  const auto p = static_cast<double>(Xp.cols() + family.grid_parameters());
  c.family = owner;
  c.coefficients = f->beta;
  c.delta_bic = ctx.n * std::log(std::max(f->rss, 1e-300) / rss0) + p * ctx.ln_n();
  c.explained_fraction = 1.0 - f->rss / rss0;
  c.rms_before_um = std::sqrt(rss0 / ctx.n);
  c.rms_after_um = std::sqrt(f->rss / ctx.n);
  const Eigen::VectorXd inverse_sd = f->cov.diagonal().cwiseSqrt().cwiseInverse();
  c.correlation = inverse_sd.asDiagonal() * f->cov * inverse_sd.asDiagonal();
  c.explanations.push_back(c.description);
  return c;
}

/// Where a hypothesis is listed when ΔBIC ties: component by component (a component's laws in the families'
/// registration order), then the wheel's.
int listing_key(const Candidate& c) {
  return c.changes.empty() ? INT_MAX : machine::index(c.changes.front().component);
}

} // namespace

std::vector<Candidate> fit_hypotheses(const Context& ctx, const ContactStates& states) {
  const Eigen::VectorXd y = ctx.setup_terms.remove(ctx.before);
  const double rss0 = y.squaredNorm();
  if (!(rss0 > 0.0) || ctx.points.size() < 3) return {};
  // Every family's hypotheses, not those the scene models already (the completed scene never lists one twice).
  std::vector<std::vector<Candidate>> per_family;
  std::vector<Candidate> all;
  for (const auto& family : ctx.options.families) {
    std::vector<Candidate> mine;
    for (Candidate& h : family->enumerate(states, ctx.options)) {
      if (ctx.options.keep_going) ctx.options.keep_going(); // a fit on 10⁶ points takes ~0.1 s, 200 of them seconds
      const std::string scene_name = family->scene_name(h);
      if (std::find(ctx.in_scene.begin(), ctx.in_scene.end(), scene_name) != ctx.in_scene.end()) continue;
      if (auto c = fitted(ctx, states, *family, family, std::move(h), y, rss0)) mine.push_back(std::move(*c));
    }
    all.insert(all.end(), mine.begin(), mine.end());
    per_family.push_back(std::move(mine));
  }
  // What each family lists of its own (a grid keeps its best point), compared with every family's fits.
  std::vector<Candidate> listed;
  for (size_t f = 0; f < per_family.size(); ++f)
    for (Candidate& c : ctx.options.families[f]->select(std::move(per_family[f]), all, ctx.options))
      listed.push_back(std::move(c));
  std::stable_sort(listed.begin(), listed.end(),
                   [](const Candidate& a, const Candidate& b) { return listing_key(a) < listing_key(b); });
  // Plausible ones by ΔBIC, then the rejected ones.
  std::stable_sort(listed.begin(), listed.end(), [](const Candidate& a, const Candidate& b) {
    if (a.is_rejected() != b.is_rejected()) return !a.is_rejected();
    return a.delta_bic < b.delta_bic;
  });
  return listed;
}

} // namespace geartopo::diagnosis::stages
