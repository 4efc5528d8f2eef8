// geartopo diagnosis — hypothesis family: one of the chain's error components drifting linearly in time over the job
// (a thermal drift in its early phase, a slide's wear). Columns: the component's sensitivity times the point's
// grinding time t (µm per mm/s or rad/s). Not tried on a job without duration.
#include "component_law.hpp"
#include "family_list.hpp"

namespace geartopo::diagnosis::families {
namespace {

class ComponentLinear final : public HypothesisFamily {
public:
  std::string_view name() const override { return "component_linear_in_time"; }
  std::vector<Candidate> enumerate(const ContactStates& states, const DiagnoseOptions& o) const override {
    std::vector<Candidate> out;
    if (!(states.job_s() > 0.0)) return out;
    for (int k : visible_components(states)) out.push_back(component_hypothesis(o.chain, k, machine::ChangeLaw::LinearInTime));
    return out;
  }
  Eigen::MatrixXd columns(const Candidate& h, const ContactStates& states) const override {
    return states.component_sensitivity_um().col(machine::index(h.changes.front().component)).cwiseProduct(states.time_s());
  }
  Eigen::VectorXd plausible_size(const Candidate& h, const ContactStates& states,
                                 const DiagnoseOptions& o) const override {
    return Eigen::VectorXd::Constant(1, plausible_change(h.changes.front(), o) / states.job_s()); // a rate
  }
  Candidate finding(Candidate h, const LinearFit& fit, const ContactStates& states,
                    const DiagnoseOptions& o) const override {
    return one_coefficient_finding(std::move(h), fit, states, o);
  }
};

} // namespace

std::shared_ptr<const HypothesisFamily> make_component_linear_in_time() { return std::make_shared<ComponentLinear>(); }

} // namespace geartopo::diagnosis::families
