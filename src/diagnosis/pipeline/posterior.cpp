// geartopo diagnosis — what the data determine of the chosen explanation (stages.hpp, PosteriorDraws): its posterior
// drawn as equally likely value sets when single values are not determined. The deviation of a library effect is linear
// in its linear parameters θ once the others (q: a time constant) are fixed, so the posterior separates:
//   p(q, θ | r) ∝ p(q) · exp(−RSS(q)/2σ̂²) · N(θ; θ̂(q), σ̂² (J(q)ᵀJ(q))⁻¹),
// θ̂(q) and RSS(q) the linear least squares at q (set-up terms removed, whitened as every fit). q on a grid over its
// allowed range (log-spaced for a positive range: a log-uniform prior, equal mass per cell), θ from its Gaussian given
// q, held inside its allowed range by drawing again. Units: each parameter's own (its key), µm for residuals.
#include "stages.hpp"

#include "geartopo/core/random.hpp"
#include "geartopo/effects/registry.hpp"

#include <algorithm>
#include <cmath>

namespace geartopo::diagnosis::stages {
namespace {

constexpr int kDraws = 200;              ///< value sets per explanation (count)
constexpr std::uint64_t kSeed = 0x6765617274;  ///< the draws' own stream: the same diagnosis draws the same sets

/// One of the explanation's parameters: its effect, its index there, its range.
struct Slot {
  size_t effect = 0, value = 0;
  double lo = 0.0, hi = 0.0;
};

/// The grid of a nonlinear parameter over its allowed range: log-spaced when it is positive.
std::vector<double> grid_over(const Slot& s, int points) {
  std::vector<double> g(static_cast<size_t>(points));
  const bool log = s.lo > 0.0;
  for (int k = 0; k < points; ++k) {
    const double f = points == 1 ? 0.5 : static_cast<double>(k) / (points - 1);
    g[static_cast<size_t>(k)] = log ? std::exp(std::log(s.lo) + f * (std::log(s.hi) - std::log(s.lo))) : s.lo + f * (s.hi - s.lo);
  }
  return g;
}

/// The linear least squares at one grid node: θ̂, its covariance per σ̂² (JᵀJ)⁻¹ and the RSS left.
struct NodeFit {
  std::vector<std::vector<double>> values; ///< per effect: every value at this node, linear ones at θ̂
  Eigen::VectorXd theta;                   ///< L
  Eigen::MatrixXd inverse;                 ///< L × L: (JᵀJ + ridge)⁻¹
  double rss = 0.0;
};

class Posterior {
public:
  Posterior(const Context& ctx, const Candidate& c) : ctx_(ctx), c_(c) {
    for (size_t e = 0; e < c.effects.size(); ++e) {
      const auto params = effects::make_effect(c.effects[e].type)->parameters();
      for (size_t k = 0; k < params.size(); ++k) {
        if (!params[k].fitted) continue;
        (params[k].linear ? linear_ : nonlinear_).push_back({e, k, params[k].lo, params[k].hi});
      }
    }
    const Eigen::Map<const Eigen::VectorXd> r(ctx.residual_before_um.data(), static_cast<Eigen::Index>(ctx.points.size()));
    judged_ = ctx.setup_terms.remove((r.array() - ctx.at_points.offset_um()).matrix());
  }

  bool drawable() const { return nonlinear_.size() <= 2 && !(linear_.empty() && nonlinear_.empty()); }

  PosteriorDraws draws() const {
    const int points = nonlinear_.empty() ? 1 : nonlinear_.size() == 1 ? 64 : 24;
    std::vector<std::vector<double>> axes;
    for (const auto& s : nonlinear_) axes.push_back(grid_over(s, points));
    // Every node of the grid (one node without nonlinear parameters), fitted.
    std::vector<NodeFit> nodes;
    const size_t count = nonlinear_.empty() ? 1 : nonlinear_.size() == 1 ? axes[0].size() : axes[0].size() * axes[1].size();
    for (size_t i = 0; i < count; ++i) {
      std::vector<std::vector<double>> values;
      for (const auto& e : c_.effects) values.push_back(e.values);
      for (size_t a = 0; a < nonlinear_.size(); ++a) {
        const size_t index = a == 0 ? i % axes[0].size() : i / axes[0].size();
        values[nonlinear_[a].effect][nonlinear_[a].value] = axes[a][index];
      }
      nodes.push_back(fit_at(std::move(values)));
    }
    // σ̂² of the best node, and each node's weight exp(−ΔRSS/2σ̂²) (equal prior mass per node).
    double best = 1e300;
    for (const auto& n : nodes) best = std::min(best, n.rss);
    const double dof = std::max(1.0, ctx_.n - ctx_.setup_terms.count() - static_cast<double>(linear_.size() + nonlinear_.size()));
    const double sigma2 = std::max(best / dof, 1e-30);
    std::vector<double> cumulative;
    double total = 0.0;
    for (const auto& n : nodes) cumulative.push_back(total += std::exp(-(n.rss - best) / (2.0 * sigma2)));
    PosteriorDraws out;
    out.grid_points = nonlinear_.empty() ? 0 : points;
    for (const auto& e : c_.effects)
      out.values.emplace_back(kDraws, static_cast<Eigen::Index>(e.values.size()));
    // A draw is a node by its weight and θ from its Gaussian there, drawn again as a whole while θ leaves its allowed
    // range: the posterior truncated to the box, so a node whose θ̂ lies outside (a time constant so long that the
    // growth it needs exceeds the range) gets the little mass it has inside.
    random::SplitMix64 rng(kSeed);
    for (int k = 0; k < kDraws; ++k) {
      const NodeFit* node = nullptr;
      Eigen::VectorXd theta;
      for (int attempt = 0; attempt < 1000; ++attempt) {
        const double u = rng.uniform() * total;
        const auto i = static_cast<size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
        node = &nodes[std::min(i, nodes.size() - 1)];
        theta = linear_draw(*node, sigma2, rng);
        if (inside(theta)) break;
      }
      theta = clamped(theta);
      auto values = node->values;
      for (size_t j = 0; j < linear_.size(); ++j) values[linear_[j].effect][linear_[j].value] = theta(static_cast<Eigen::Index>(j));
      for (size_t e = 0; e < values.size(); ++e)
        for (size_t v = 0; v < values[e].size(); ++v) out.values[e](k, static_cast<Eigen::Index>(v)) = values[e][v];
    }
    return out;
  }

private:
  /// The explanation's deviation at the points with these values (n, µm, set-up terms removed).
  Eigen::VectorXd judged_field(const std::vector<std::vector<double>>& values) const {
    std::vector<std::unique_ptr<effects::Effect>> owned;
    std::vector<const effects::Effect*> list;
    for (size_t e = 0; e < c_.effects.size(); ++e) {
      owned.push_back(effects::make_effect(c_.effects[e].type, values[e], ctx_.setup));
      list.push_back(owned.back().get());
    }
    return ctx_.setup_terms.remove(Eigen::VectorXd(ctx_.at_points.deviation_um(list, ctx_.options.threads)));
  }

  NodeFit fit_at(std::vector<std::vector<double>> values) const {
    // The part of the linear parameters at zero (what the fixed values make), then one column per linear parameter.
    for (const auto& s : linear_) values[s.effect][s.value] = 0.0;
    const Eigen::VectorXd fixed = judged_field(values);
    const auto n = judged_.size();
    Eigen::MatrixXd J(n, static_cast<Eigen::Index>(linear_.size())); // n × L
    for (size_t j = 0; j < linear_.size(); ++j) {
      auto unit = values;
      unit[linear_[j].effect][linear_[j].value] = 1.0;
      J.col(static_cast<Eigen::Index>(j)) = judged_field(unit) - fixed;
    }
    const Eigen::VectorXd y = judged_ - fixed;
    NodeFit f;
    f.values = std::move(values);
    if (J.cols() == 0) {
      f.rss = y.squaredNorm();
      return f;
    }
    Eigen::MatrixXd A = J.transpose() * J; // L × L
    A.diagonal().array() += ctx_.options.covariance_ridge * std::max(1.0, A.trace());
    f.inverse = A.inverse();
    f.theta = f.inverse * (J.transpose() * y);
    f.rss = (y - J * f.theta).squaredNorm();
    return f;
  }

  /// θ from N(θ̂, σ̂² (JᵀJ)⁻¹) (L; empty without linear parameters).
  Eigen::VectorXd linear_draw(const NodeFit& node, double sigma2, random::SplitMix64& rng) const {
    const auto L = static_cast<Eigen::Index>(linear_.size());
    if (L == 0) return {};
    const Eigen::MatrixXd factor = Eigen::LLT<Eigen::MatrixXd>(sigma2 * node.inverse).matrixL();
    Eigen::VectorXd z(L);
    for (auto& v : z) v = rng.normal();
    return node.theta + factor * z;
  }

  bool inside(const Eigen::VectorXd& theta) const {
    for (Eigen::Index j = 0; j < theta.size(); ++j)
      if (!(theta(j) >= linear_[static_cast<size_t>(j)].lo && theta(j) <= linear_[static_cast<size_t>(j)].hi)) return false;
    return true;
  }

  /// Held inside the allowed ranges: only when a thousand draws in a row left them (a posterior nearly all outside).
  Eigen::VectorXd clamped(Eigen::VectorXd theta) const {
    for (Eigen::Index j = 0; j < theta.size(); ++j)
      theta(j) = std::clamp(theta(j), linear_[static_cast<size_t>(j)].lo, linear_[static_cast<size_t>(j)].hi);
    return theta;
  }

  const Context& ctx_;
  const Candidate& c_;
  std::vector<Slot> linear_, nonlinear_;
  Eigen::VectorXd judged_; ///< n: the residual with the set-up terms removed, less the model's mean-allowance offset
};

} // namespace

std::optional<PosteriorDraws> posterior_draws(const Context& ctx, const std::optional<Candidate>& chosen) {
  if (!chosen || chosen->family || chosen->effects.empty()) return std::nullopt;
  bool open = false;
  for (const auto& params : chosen->parameters)
    for (const auto& p : params) open = open || (p.fitted && !p.determined);
  if (!open) return std::nullopt;
  const Posterior posterior(ctx, *chosen);
  if (!posterior.drawable()) return std::nullopt;
  return posterior.draws();
}

} // namespace geartopo::diagnosis::stages
