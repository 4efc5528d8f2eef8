// geartopo diagnosis — hypothesis family: one of the chain's error components approaching a steady state,
// δe(t) = c_∞ (1 − e^(−t/τ)) (the first-order thermal law of a machine element warming up). τ on a grid over the job
// (1/8 … 2 jobs, charged ln n as a parameter): with one or two teeth measured a time constant is rarely determined,
// and a law whose τ the data do not fix is reported as the constant or linear drift it then looks like (select).
#include "component_law.hpp"
#include "family_list.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace geartopo::diagnosis::families {
namespace {

using machine::ChangeLaw;

bool same_component(const Candidate& a, const Candidate& b) {
  return !a.changes.empty() && !b.changes.empty() && a.changes.front().component == b.changes.front().component;
}

class ComponentSteadyState final : public HypothesisFamily {
public:
  std::string_view name() const override { return "component_steady_state"; }
  int grid_parameters() const override { return 1; } // τ
  std::vector<Candidate> enumerate(const ContactStates& states, const DiagnoseOptions& o) const override {
    std::vector<Candidate> out;
    if (!(states.job_s() > 0.0)) return out;
    for (int k : visible_components(states))
      for (double f : kJobFractions) out.push_back(component_hypothesis(o.chain, k, ChangeLaw::SteadyState, f * states.job_s()));
    return out;
  }
  Eigen::MatrixXd columns(const Candidate& h, const ContactStates& states) const override {
    const double tau = h.changes.front().time_constant_s;
    return states.component_sensitivity_um()
        .col(machine::index(h.changes.front().component))
        .cwiseProduct(Eigen::VectorXd(1.0 - (-(states.time_s().array() / tau)).exp()));
  }
  Eigen::VectorXd plausible_size(const Candidate& h, const ContactStates&, const DiagnoseOptions& o) const override {
    return Eigen::VectorXd::Constant(1, plausible_change(h.changes.front(), o));
  }
  Candidate finding(Candidate h, const LinearFit& fit, const ContactStates& states,
                    const DiagnoseOptions& o) const override {
    return one_coefficient_finding(std::move(h), fit, states, o);
  }
  /// A steady state whose time constant the data do not fix is no finding: kept only where it beats the same
  /// component's constant and linear laws by the threshold, and then only its best τ, with its 1σ range on the grid.
  std::vector<Candidate> select(std::vector<Candidate> mine, const std::vector<Candidate>& all,
                                const DiagnoseOptions& o) const override {
    std::vector<Candidate> kept;
    for (size_t a = 0; a < mine.size(); ++a) {
      bool keep = true;
      for (size_t b = 0; b < mine.size() && keep; ++b)
        keep = b == a || !same_component(mine[a], mine[b]) || !(mine[b].delta_bic < mine[a].delta_bic);
      for (const Candidate& other : all) {
        if (!keep) break;
        const bool simpler = !other.changes.empty() && (other.changes.front().law == ChangeLaw::Constant ||
                                                        other.changes.front().law == ChangeLaw::LinearInTime);
        keep = !(simpler && same_component(mine[a], other) && mine[a].delta_bic > other.delta_bic - o.bic_threshold);
      }
      if (keep) kept.push_back(with_tau_range(mine[a], mine));
    }
    return kept;
  }

private:
  static constexpr double kJobFractions[] = {0.125, 0.25, 0.5, 1.0, 2.0};

  /// The kept τ with its 1σ range on the grid: the τ of the same component whose fit is within
  /// Δ(−2 ln L) = n ln(RSS_τ/RSS_best) ≤ 1 of the best (the same parameter count, so that is their ΔBIC difference).
  static Candidate with_tau_range(Candidate c, const std::vector<Candidate>& grid) {
    const double tau = c.changes.front().time_constant_s;
    double lo = tau, hi = tau;
    for (const Candidate& g : grid)
      if (same_component(c, g) && g.delta_bic - c.delta_bic <= 1.0) {
        lo = std::min(lo, g.changes.front().time_constant_s);
        hi = std::max(hi, g.changes.front().time_constant_s);
      }
    for (auto& p : c.parameters.front())
      if (p.key == "time_constant_s") p.uncertainty = 0.5 * (hi - lo);
    c.description += lo < hi ? fmt::format(" (1σ: {:.0f} … {:.0f} s, on a grid of 1/8 … 2 jobs)", lo, hi)
                             : std::string(" (1σ: within the grid's factor 2 around it)");
    return c;
  }
};

} // namespace

std::shared_ptr<const HypothesisFamily> make_component_steady_state() {
  return std::make_shared<ComponentSteadyState>();
}

} // namespace geartopo::diagnosis::families
