// geartopo diagnosis — hypothesis family: one of the chain's error components changed by a constant since the map was
// measured (a machine element knocked, re-clamped or re-adjusted). Columns: the component's first-order sensitivity
// at the points' generating poses (µm per mm or rad).
#include "component_law.hpp"
#include "family_list.hpp"

namespace geartopo::diagnosis::families {
namespace {

class ComponentConstant final : public HypothesisFamily {
public:
  std::string_view name() const override { return "component_constant"; }
  std::vector<Candidate> enumerate(const ContactStates& states, const DiagnoseOptions& o) const override {
    std::vector<Candidate> out;
    for (int k : visible_components(states)) out.push_back(component_hypothesis(o.chain, k, machine::ChangeLaw::Constant));
    return out;
  }
  Eigen::MatrixXd columns(const Candidate& h, const ContactStates& states) const override {
    return states.component_sensitivity_um().col(machine::index(h.changes.front().component));
  }
  Eigen::VectorXd plausible_size(const Candidate& h, const ContactStates&, const DiagnoseOptions& o) const override {
    return Eigen::VectorXd::Constant(1, plausible_change(h.changes.front(), o));
  }
  Candidate finding(Candidate h, const LinearFit& fit, const ContactStates& states,
                    const DiagnoseOptions& o) const override {
    return one_coefficient_finding(std::move(h), fit, states, o);
  }
};

} // namespace

std::shared_ptr<const HypothesisFamily> make_component_constant() { return std::make_shared<ComponentConstant>(); }

} // namespace geartopo::diagnosis::families
