// geartopo diagnosis — the hypothesis families' shared parts (hypothesis_family.hpp): the contact states every family
// reads, the defaults of the interface, and the registry of the library's families. Units: µm, s, rad.
#include "geartopo/diagnosis/hypothesis_family.hpp"

#include "../setup_terms.hpp"
#include "family_list.hpp"

#include <algorithm>
#include <set>

namespace geartopo::diagnosis {

HypothesisFamilies default_hypothesis_families() {
  static const HypothesisFamilies list = {
#define GEARTOPO_MAKE_FAMILY(name) families::make_##name(),
      GEARTOPO_HYPOTHESIS_FAMILY_LIST(GEARTOPO_MAKE_FAMILY)
#undef GEARTOPO_MAKE_FAMILY
  };
  return list;
}

ContactStates::ContactStates(const grinding::GrindingSetup& setup, const EffectContribution& at,
                             const SetupTermModel* terms, int threads, const std::vector<int>& teeth,
                             std::function<void()> keep_going)
    : setup_(setup), at_(at), terms_(terms), threads_(threads),
      teeth_measured_(static_cast<int>(std::set<int>(teeth.begin(), teeth.end()).size())),
      keep_going_(std::move(keep_going)) {}

const Eigen::MatrixXd& ContactStates::component_sensitivity_um() const {
  if (!sensitivity_) sensitivity_ = at_.component_sensitivity_um(threads_, keep_going_);
  return *sensitivity_;
}

const Eigen::VectorXd& ContactStates::time_s() const {
  if (!time_) {
    time_.emplace(static_cast<Eigen::Index>(size()));
    for (std::size_t i = 0; i < size(); ++i) (*time_)(static_cast<Eigen::Index>(i)) = at_.path_point(i).time_s;
  }
  return *time_;
}

const Eigen::VectorXd& ContactStates::c_rad() const {
  if (!c_) {
    c_.emplace(static_cast<Eigen::Index>(size()));
    for (std::size_t i = 0; i < size(); ++i) (*c_)(static_cast<Eigen::Index>(i)) = at_.path_point(i).q.c;
  }
  return *c_;
}

double ContactStates::job_s() const {
  const auto& strokes = setup_.path().strokes();
  const double last = size() > 0 ? time_s().maxCoeff() : 0.0;
  return std::max(strokes.empty() ? 0.0 : strokes.back().t_end_s, last);
}

Eigen::MatrixXd ContactStates::judged(const Eigen::MatrixXd& X) const {
  if (!terms_) return X;
  Eigen::MatrixXd out(X.rows(), X.cols());
  for (Eigen::Index j = 0; j < X.cols(); ++j) out.col(j) = terms_->remove(Eigen::VectorXd(X.col(j)));
  return out;
}

Eigen::VectorXd ContactStates::deviation_um(const std::vector<const effects::Effect*>& effects) const {
  return at_.deviation_um(effects, threads_);
}

std::string HypothesisFamily::scene_name(const Candidate& h) const {
  return h.changes.empty() && !h.effects.empty() ? h.effects.front().type : h.name();
}

std::vector<Candidate> HypothesisFamily::select(std::vector<Candidate> mine, const std::vector<Candidate>&,
                                                const DiagnoseOptions&) const {
  return mine;
}

Eigen::VectorXd hypothesis_field(const Candidate& h, const ContactStates& states) {
  if (!h.family) throw std::invalid_argument("hypothesis_field: " + h.name() + " is no hypothesis beyond the library");
  return h.family->columns(h, states) * h.coefficients;
}

} // namespace geartopo::diagnosis
