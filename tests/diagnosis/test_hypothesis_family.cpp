// geartopo tests — a hypothesis family registered from a test file (docs/adding-an-effect.md, "Adding a hypothesis
// family"): one class here and one line in the options, and diagnose tries it beside the library's families.
//
// The family: the X infeed steps by s at every stroke (δX = s·k on the k-th stroke of the job: a wheel-wear
// compensation that over-feeds by a fixed amount per stroke). Linear in s; its columns are X's first-order sensitivity
// (δ_xx, the X slide standing further than commanded: the same as commanding X + δ) times the stroke index. The truth
// is written from the physics through the ideal chain (independent_truth::axis_offset_um with δX = s·k), not with the
// family's columns. Units: µm per stroke, mm inside.
#include "independent_truth.hpp"

#include "geartopo/diagnosis/hypothesis_family.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <random>

namespace {

using namespace geartopo;
using namespace independent_truth;

class XStepPerStroke final : public diagnosis::HypothesisFamily {
public:
  std::string_view name() const override { return "x_step_per_stroke"; }
  std::vector<diagnosis::Candidate> enumerate(const diagnosis::ContactStates&,
                                              const diagnosis::DiagnoseOptions&) const override {
    diagnosis::Candidate h;
    h.label = "x_step_per_stroke";
    return {h};
  }
  Eigen::MatrixXd columns(const diagnosis::Candidate&, const diagnosis::ContactStates& states) const override {
    Eigen::VectorXd k(static_cast<Eigen::Index>(states.size())); // each point's stroke index in the job
    for (std::size_t i = 0; i < states.size(); ++i)
      k(static_cast<Eigen::Index>(i)) = states.setup().path().stroke_index(states.at().path_point(i).space);
    return states.component_sensitivity_um().col(machine::index(machine::ComponentId::delta_xx)).cwiseProduct(k);
  }
  Eigen::VectorXd plausible_size(const diagnosis::Candidate&, const diagnosis::ContactStates&,
                                 const diagnosis::DiagnoseOptions&) const override {
    return Eigen::VectorXd::Constant(1, 0.01); // mm per stroke
  }
  diagnosis::Candidate finding(diagnosis::Candidate c, const diagnosis::LinearFit& fit, const diagnosis::ContactStates&,
                               const diagnosis::DiagnoseOptions&) const override {
    const double step_um = 1e3 * fit.beta(0), sd_um = 1e3 * std::sqrt(fit.cov(0, 0));
    c.parameters.push_back({{"x_step_um_per_stroke", step_um, sd_um, true}});
    c.description = fmt::format("the X infeed steps by {:.3f} ± {:.3f} µm per stroke", step_um, sd_um);
    return c;
  }
};

std::vector<measurement::MeasuredPoint> measure_staircase(double step_um, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.5);
  const auto& l = two_teeth();
  auto pts = l.points;
  for (size_t i = 0; i < pts.size(); ++i) {
    machine::AxisPose dq{};
    dq.x = 1e-3 * step_um * bench().setup.path().stroke_index(l.contacts[i].pp.space);
    pts[i].deviation_um += axis_offset_um(l.contacts[i], dq) + noise(rng);
  }
  return pts;
}

const diagnosis::Candidate* listed(const diagnosis::Diagnosis& d, const std::string& name) {
  for (const auto& h : d.hypotheses)
    if (h.name() == name) return &h;
  return nullptr;
}

TEST(HypothesisFamily, OneRegisteredFromATestIsTriedBesideTheLibrarys) {
  const double step_um = 0.15; // × 69 strokes between teeth 1 and 18's spaces: ~10 µm across the job
  const auto pts = measure_staircase(step_um, 3);
  diagnosis::DiagnoseOptions o;
  o.noise_um = 0.5;
  o.families.push_back(std::make_shared<XStepPerStroke>()); // the one line
  const auto d = diagnosis::diagnose(bench().setup, bench().process(), pts, bench().effect_types(), o);
  SCOPED_TRACE(d.verdict);
  const auto* h = listed(d, "x_step_per_stroke");
  ASSERT_NE(h, nullptr);
  ASSERT_EQ(h->family->name(), "x_step_per_stroke");
  const auto& p = h->parameters.front().front();
  EXPECT_NEAR(p.value, step_um, 2.0 * p.uncertainty);
  // The truth explains the residual to the noise: the family's hypothesis is named, or one the flanks cannot tell from
  // it is, with it in its class.
  ASSERT_TRUE(d.beyond_library);
  const bool named = d.chosen->name() == "x_step_per_stroke" ||
                     std::find(d.chosen->equivalent.begin(), d.chosen->equivalent.end(), "x_step_per_stroke") !=
                         d.chosen->equivalent.end();
  EXPECT_TRUE(named);
  if (d.chosen->name() == "x_step_per_stroke") {
    EXPECT_NE(d.verdict.find("steps by"), std::string::npos);
  }
  // Without the line, nothing of it.
  diagnosis::DiagnoseOptions without;
  without.noise_um = 0.5;
  const auto plain = diagnosis::diagnose(bench().setup, bench().process(), pts, bench().effect_types(), without);
  EXPECT_EQ(listed(plain, "x_step_per_stroke"), nullptr);
}

} // namespace
