// geartopo diagnosis — what the component families share (component_law.hpp). Units: mm, rad inside; µm, µrad in files.
#include "component_law.hpp"

#include "geartopo/core/uncertain_value.hpp"

#include <fmt/format.h>

#include <cmath>

namespace geartopo::diagnosis::families {

using machine::ChangeLaw;

std::vector<int> visible_components(const ContactStates& states) {
  std::vector<int> out;
  const Eigen::MatrixXd& S = states.component_sensitivity_um(); // n × 43
  for (int k = 0; k < machine::kComponentCount; ++k)
    if (!S.col(k).isZero(0.0)) out.push_back(k);
  return out;
}

Candidate component_hypothesis(const machine::KinematicChain* chain, int component, ChangeLaw law, double time_constant_s,
                              int order) {
  Candidate c;
  c.chain = chain;
  machine::ComponentChange ch;
  ch.component = machine::component_at(component), ch.law = law, ch.time_constant_s = time_constant_s, ch.order = order;
  c.changes.push_back(ch);
  return c;
}

double plausible_change(const machine::ComponentChange& ch, const DiagnoseOptions& o) {
  return machine::info(ch.component).quantity == machine::Quantity::Length ? o.plausible_change_um * 1e-3
                                                                            : o.plausible_change_urad * 1e-6;
}

std::string unit_of(machine::Quantity q) { return q == machine::Quantity::Length ? "µm" : "µrad"; }

Candidate one_coefficient_finding(Candidate c, const LinearFit& f, const ContactStates& states, const DiagnoseOptions& o) {
  auto& ch = c.changes.front();
  const auto q = machine::info(ch.component).quantity;
  const double sd = std::sqrt(f.cov(0, 0)), job_s = states.job_s();
  ch.size = f.beta(0);
  // A drift's reach is its rate over the whole job; a constant or a steady state reaches its size.
  const double per = ch.law == ChangeLaw::LinearInTime ? job_s : 1.0;
  const double reach = std::abs(ch.size) * per, reach_sd = sd * per;
  c.change_sd.push_back(sd);
  const double scale = machine::file_per_internal(ch.law, q);
  std::vector<FittedParameter> params{{machine::size_key(ch.law, q), ch.size * scale, sd * scale, true}};
  if (ch.law == ChangeLaw::SteadyState) params.push_back({"time_constant_s", ch.time_constant_s, 0.0, true});
  c.parameters.push_back(std::move(params));
  std::string text = machine::describe(ch, text::with_uncertainty(ch.size * scale, sd * scale, true), {}, c.chain);
  if (ch.law == ChangeLaw::LinearInTime)
    text += fmt::format(" ({:+.3g} {} over the {:.0f}-min job)", ch.size * job_s * (scale / 60.0), unit_of(q),
                        job_s / 60.0);
  c.description = text;
  const double limit = plausible_change(ch, o);
  if (reach - 2.0 * reach_sd > limit) {
    const double file = q == machine::Quantity::Length ? 1e3 : 1e6;
    Decision d{Reason::implausible_change, std::string(machine::info(c.chain, ch.component).name), {},
               {{"reach", reach * file}, {"limit", limit * file}}};
    d.unit = unit_of(q);
    c.rejection = std::move(d);
  }
  return c;
}

} // namespace geartopo::diagnosis::families
