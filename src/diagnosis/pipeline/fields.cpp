// geartopo diagnosis — what a library explanation's parameters can do at the measured points, and how much of a field
// lies in it (stages.hpp): the look-alike tests of the pairs, the families and the alternatives. Units: µm.
#include "stages.hpp"

#include "geartopo/effects/registry.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace geartopo::diagnosis::stages {

Eigen::MatrixXd library_columns(const Context& ctx, const Candidate& c) {
  const auto field = [&](const std::vector<scene::EffectSpec>& specs) {
    std::vector<std::unique_ptr<effects::Effect>> owned;
    std::vector<const effects::Effect*> list;
    for (const auto& e : specs) {
      owned.push_back(effects::make_effect(e.type, e.values, ctx.setup));
      list.push_back(owned.back().get());
    }
    return Eigen::VectorXd(ctx.at_points.deviation_um(list, ctx.options.threads));
  };
  // Central differences, a step of 10⁻³ of the value or its typical size.
  std::vector<Eigen::VectorXd> cols;
  for (size_t e = 0; e < c.effects.size(); ++e) {
    const auto specs = effects::make_effect(c.effects[e].type)->parameters();
    for (size_t k = 0; k < specs.size() && k < c.effects[e].values.size(); ++k) {
      if (!specs[k].fitted) continue;
      const double step = 1e-3 * std::max(std::abs(c.effects[e].values[k]), specs[k].typical);
      auto plus = c.effects, minus = c.effects;
      plus[e].values[k] += step, minus[e].values[k] -= step;
      cols.push_back(ctx.setup_terms.remove(Eigen::VectorXd((field(plus) - field(minus)) / (2.0 * step))));
    }
  }
  Eigen::MatrixXd J(static_cast<Eigen::Index>(ctx.at_points.size()), static_cast<Eigen::Index>(cols.size())); // n × P
  for (size_t j = 0; j < cols.size(); ++j) J.col(static_cast<Eigen::Index>(j)) = cols[j];
  return J;
}

Eigen::VectorXd explanation_field(const Context& ctx, const Candidate& c) {
  std::vector<std::unique_ptr<effects::Effect>> owned;
  std::vector<const effects::Effect*> list;
  for (const auto& e : c.effects) {
    owned.push_back(effects::make_effect(e.type, e.values, ctx.setup));
    list.push_back(owned.back().get());
  }
  return ctx.setup_terms.remove(Eigen::VectorXd(ctx.at_points.deviation_um(list, ctx.options.threads)));
}

double share_of_field_in_span(const Eigen::VectorXd& f, const Eigen::MatrixXd& B) {
  // The projection by least squares, never the n × n Q, which for 10⁵ points would need 80 GB.
  if (B.cols() == 0 || f.norm() == 0.0) return 0.0;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(B);
  return (B * qr.solve(f)).norm() / f.norm();
}

} // namespace geartopo::diagnosis::stages
