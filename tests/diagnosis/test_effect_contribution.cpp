// The fit's stored-contact evaluation of the effects (diagnosis/effect_contribution.hpp) against the simulator's own
// first-order model, diagnosis::predict(…, Method::Linear) over effects::EffectsProcess — the independent computation:
// it finds each point's generating pose, contact and axis Jacobian afresh and composes the twist through the process
// interface. Random points on every tooth and flank, random parameter values over each effect's whole allowed range.
#include "geartopo/diagnosis/diagnose.hpp"
#include "geartopo/diagnosis/effect_contribution.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/diagnosis/prediction.hpp"
#include "geartopo/effects/effects_process.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/grinding/machine_process.hpp"
#include "geartopo/machine/machine_model.hpp"
#include "geartopo/workbench/workbench.hpp"

#include "flank_points.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace geartopo;

namespace {

const workbench::Workbench& contribution_scene() {
  static const workbench::Workbench b(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml");
  return b;
}

using geartopo::test::random_flank_points;

// Each fitted parameter uniform over its allowed range [lo, hi] (counts rounded to whole numbers).
void randomise(effects::Effect& e, std::mt19937_64& rng) {
  auto v = e.values();
  for (size_t k = 0; k < v.size(); ++k) {
    const auto& s = e.parameters()[k];
    if (!s.fitted) continue;
    v[k] = std::uniform_real_distribution<double>(s.lo, s.hi)(rng);
    if (s.whole) v[k] = std::round(v[k]);
  }
  e.set_values(v);
}

// Largest |stored-contact − predict| (µm) over the points, for these effects.
double largest_disagreement_um(const diagnosis::EffectContribution& at_points,
                               const std::vector<measurement::MeasuredPoint>& pts,
                               const std::vector<std::unique_ptr<effects::Effect>>& effs, double& largest_value_um) {
  const auto& setup = contribution_scene().setup;
  const grinding::IdealProcess ideal;
  const effects::EffectsProcess process(ideal, effs);
  const auto truth = diagnosis::predict(setup, process, pts, grinding::Method::Linear, 1);
  const Eigen::VectorXd got = at_points.evaluate_um(effs, 1);
  double worst = 0.0;
  for (size_t i = 0; i < pts.size(); ++i) {
    worst = std::max(worst, std::abs(got(static_cast<Eigen::Index>(i)) - truth[i]));
    largest_value_um = std::max(largest_value_um, std::abs(truth[i]));
  }
  return worst;
}

// Rounding only: the two paths associate the same products differently (a_qᵀδq against n·(J δq), …); at deviations
// of a few hundred µm that is ~1e-12 µm. 1e-9 µm leaves room for the largest parameter values and is still a million
// times below anything a model difference (a wrong pose, time stamp or sign) would give.
constexpr double kRoundingUm = 1e-9;

TEST(EffectContribution, EqualsTheSimulatorsLinearModelForEveryLibraryEffect) {
  const auto& setup = contribution_scene().setup;
  const auto pts = random_flank_points(setup.geometry(), 400, 7);
  const diagnosis::EffectContribution at_points(setup, pts, 1);
  ASSERT_EQ(at_points.size(), pts.size());
  std::mt19937_64 rng(11);
  double worst_um = 0.0;
  for (const auto& type : effects::effect_types()) {
    for (int draw = 0; draw < 5; ++draw) {
      std::vector<std::unique_ptr<effects::Effect>> effs;
      effs.push_back(effects::make_effect(type));
      effs.back()->bind(setup);
      randomise(*effs.back(), rng);
      double largest = 0.0;
      const double disagreement = largest_disagreement_um(at_points, pts, effs, largest);
      worst_um = std::max(worst_um, disagreement);
      EXPECT_LE(disagreement, kRoundingUm) << type << ", draw " << draw;
      EXPECT_GT(largest, 0.01) << type << ": the draw must make a deviation, or the comparison proves nothing";
    }
  }
  RecordProperty("largest_disagreement_um", fmt::format("{:.3g}", worst_um)); // docs/diagnosis.md quotes it
}

TEST(EffectContribution, EqualsTheSimulatorsLinearModelForAllEffectsTogether) {
  const auto& setup = contribution_scene().setup;
  const auto pts = random_flank_points(setup.geometry(), 400, 8);
  const diagnosis::EffectContribution at_points(setup, pts, 1);
  std::mt19937_64 rng(12);
  for (int draw = 0; draw < 5; ++draw) {
    std::vector<std::unique_ptr<effects::Effect>> effs;
    for (const auto& type : effects::effect_types()) {
      effs.push_back(effects::make_effect(type));
      effs.back()->bind(setup);
      randomise(*effs.back(), rng);
    }
    double largest = 0.0;
    EXPECT_LE(largest_disagreement_um(at_points, pts, effs, largest), kRoundingUm) << "draw " << draw;
  }
}

TEST(EffectContribution, DoesNotDependOnTheThreadCount) {
  const auto& setup = contribution_scene().setup;
  const auto pts = random_flank_points(setup.geometry(), 3000, 9); // several parallel chunks
  const diagnosis::EffectContribution one(setup, pts, 1), two(setup, pts, 2);
  std::mt19937_64 rng(13);
  std::vector<std::unique_ptr<effects::Effect>> effs;
  for (const auto& type : effects::effect_types()) {
    effs.push_back(effects::make_effect(type));
    effs.back()->bind(setup);
    randomise(*effs.back(), rng);
  }
  const Eigen::VectorXd a = one.evaluate_um(effs, 1), b = two.evaluate_um(effs, 2), c = one.evaluate_um(effs, 2);
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a(i), b(i)) << "point " << i; // bitwise: every point is computed by one thread, in one order
    ASSERT_EQ(a(i), c(i)) << "point " << i;
  }
}

// ParameterSpec::linear, the claim the fit's closed-form Jacobian columns rest on (effect_fit.cpp): the fit's column
// b_k — EffectContribution::deviation_um with θ_k = 1, the effect's other linear parameters 0, the rest at random
// values — equals the central finite difference of the simulator's own first-order model (diagnosis::predict through
// EffectsProcess, not the stored contact state) in θ_k, and Σ θ_k b_k is that model's whole deviation (zero when the
// linear parameters are). A parameter wrongly declared linear would miss by the size of its curvature (e.g. a time
// constant: µm). Rounding bound: a column is the deviation per 1 µm of θ_k, and the commanded axes minus the nominal
// ones ((q + δq) − q, as EffectsProcess forms them) round at ε·|q| ≈ 2e-16 · 1000 mm = 2e-13 mm = 2e-10 µm per
// column; Σ θ_k b_k multiplies that by |θ_k| ≤ 500 µm per µm (the allowed ranges): ≤ 1e-7 µm. 1e-6 µm is that with a
// margin, a thousand times below a nanometre and a million times below a wrong claim.
constexpr double kColumnRoundingUm = 1e-6;

TEST(EffectContribution, LinearParametersAreTheClaimedColumnsOfTheUncachedModel) {
  const auto& setup = contribution_scene().setup;
  const auto pts = random_flank_points(setup.geometry(), 300, 17);
  const diagnosis::EffectContribution at_points(setup, pts, 1);
  const grinding::IdealProcess ideal;
  const auto uncached_um = [&](const effects::Effect& e) { // the first-order model found afresh (µm, no offset)
    const effects::EffectsProcess process(ideal, {&e});
    auto d = diagnosis::predict(setup, process, pts, grinding::Method::Linear, 1);
    for (double& v : d) v -= at_points.offset_um();
    return d;
  };
  std::mt19937_64 rng(19);
  int columns_checked = 0;
  for (const auto& type : effects::effect_types()) {
    auto e = effects::make_effect(type);
    e->bind(setup);
    std::vector<size_t> linear;
    for (size_t k = 0; k < e->parameters().size(); ++k)
      if (e->parameters()[k].linear) linear.push_back(k);
    if (linear.empty()) continue;
    for (int draw = 0; draw < 3; ++draw) {
      randomise(*e, rng);
      const std::vector<double> values = e->values();
      std::vector<double> sum(pts.size(), 0.0); // Σ θ_k b_k
      for (size_t k : linear) {
        auto unit_effect = e->clone();
        std::vector<double> unit = values;
        for (size_t m : linear) unit[m] = 0.0;
        unit[k] = 1.0;
        unit_effect->set_values(unit);
        const effects::Effect* one[] = {unit_effect.get()};
        const Eigen::VectorXd column = at_points.deviation_um(one, 1); // µm per file unit of θ_k
        const double h = e->parameters()[k].typical;
        std::vector<double> plus = values, minus = values;
        plus[k] += h, minus[k] -= h;
        e->set_values(plus);
        const auto up = uncached_um(*e);
        e->set_values(minus);
        const auto down = uncached_um(*e);
        e->set_values(values);
        double worst = 0.0, size = 0.0;
        for (size_t i = 0; i < pts.size(); ++i) {
          const double difference = (up[i] - down[i]) / (2.0 * h);
          worst = std::max(worst, std::abs(column(static_cast<Eigen::Index>(i)) - difference));
          size = std::max(size, std::abs(difference));
          sum[i] += values[k] * column(static_cast<Eigen::Index>(i));
        }
        EXPECT_LE(worst, kColumnRoundingUm) << type << "." << e->parameters()[k].key << ", draw " << draw;
        EXPECT_GT(size, 1e-4) << type << "." << e->parameters()[k].key << ": the column must be seen at the points";
        ++columns_checked;
      }
      const auto whole = uncached_um(*e);
      for (size_t i = 0; i < pts.size(); ++i)
        ASSERT_LE(std::abs(sum[i] - whole[i]), kColumnRoundingUm) << type << ", draw " << draw << ", point " << i;
    }
  }
  // The library's linear parameters: thermal 2, wear 1, deflection 1, profile 2, lag 1, runout 2, flank profile 4,
  // profile wear 2, flank waviness 4.
  EXPECT_EQ(columns_checked, 3 * 19);
}

// The whole diagnosis (every fit runs on EffectContribution) on the truth scene's thermal drift, teeth 1 and 18: the
// same ranking, ΔBIC, parameters and verdict, to the last bit, on one thread and on two.
TEST(EffectContribution, DiagnosisIsIdenticalOnOneAndTwoThreads) {
  const workbench::Workbench truth(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml");
  const auto pts = measurement::measured_points(diagnosis::synthesize(truth.setup, truth.process(), diagnosis::SynthOptions{}),
                                                truth.setup.geometry(), "synthetic");
  const auto& model = contribution_scene();
  diagnosis::DiagnoseOptions o;
  o.threads = 1;
  const auto one = diagnosis::diagnose(model.setup, model.process(), pts, model.effect_types(), o);
  o.threads = 2;
  const auto two = diagnosis::diagnose(model.setup, model.process(), pts, model.effect_types(), o);
  ASSERT_EQ(one.ranked.size(), two.ranked.size());
  for (size_t k = 0; k < one.ranked.size(); ++k) {
    EXPECT_EQ(one.ranked[k].name(), two.ranked[k].name());
    EXPECT_EQ(one.ranked[k].delta_bic, two.ranked[k].delta_bic) << one.ranked[k].name();
    for (size_t e = 0; e < one.ranked[k].parameters.size(); ++e)
      for (size_t j = 0; j < one.ranked[k].parameters[e].size(); ++j) {
        EXPECT_EQ(one.ranked[k].parameters[e][j].value, two.ranked[k].parameters[e][j].value);
        EXPECT_EQ(one.ranked[k].parameters[e][j].uncertainty, two.ranked[k].parameters[e][j].uncertainty);
      }
  }
  EXPECT_EQ(one.verdict, two.verdict);
  ASSERT_TRUE(one.chosen.has_value());
  EXPECT_EQ(one.chosen->name(), "thermal_drift"); // the truth scene's hidden effect
}

// The machine-element hypotheses' columns on the CFXZAY against what the same constant in the error map grinds through
// MachineProcess (first order): the map acts at the machine's axes, Z = z + z₀ (the gear's datum face z₀ =
// machine.datum_face_z_mm above the C table's face), its twist referred back to the datum by Tz(−z₀). A column taken
// at the path's own z (as it was) put the C table and the X slide z₀ too close to the wheel and S_xz's lever −Z·S_xz
// short by z₀: per µrad of ε_xx, ε_yx, ε_xc, ε_yc, S_xz, E_AOC or E_BOC it differed from the map by 0.14 … 0.26 µm
// where the map grinds 0.21 … 0.44 µm; the other 36 components agreed.
TEST(EffectContribution, ComponentColumnsOnTheCfxzayAreWhatTheMapGrinds) {
  const auto& wb = contribution_scene();
  const double z0 = wb.scene.machine.datum_face_z_mm;
  ASSERT_GT(z0, 100.0); // the test says nothing about the datum with the datum at the table
  const auto pts = random_flank_points(wb.setup.geometry(), 40, 4711);
  const diagnosis::EffectContribution at_points(wb.setup, pts, 1, wb.scene.machine.chain, z0);
  const Eigen::MatrixXd S = at_points.component_sensitivity_um(1); // n × 43, µm per mm or per rad
  for (int k = 0; k < machine::kComponentCount; ++k) {
    const auto id = machine::component_at(k);
    const bool angle = machine::info(id).quantity == machine::Quantity::Angle;
    const machine::MachineModel model(machine::Strokes::skmc_1200w(),
                                      {machine::ErrorSource::constant(id, 1.0, angle ? "urad" : "um")});
    const grinding::MachineProcess process(model, z0);
    const auto truth = diagnosis::predict(wb.setup, process, pts, grinding::Method::Linear, 1);
    double worst = 0.0, largest = 0.0;
    for (size_t i = 0; i < pts.size(); ++i) {
      const double column = S(static_cast<Eigen::Index>(i), k) * (angle ? 1e-6 : 1e-3);
      const double map = truth[i] - at_points.offset_um();
      worst = std::max(worst, std::abs(column - map));
      largest = std::max(largest, std::abs(map));
    }
    // Per 1 µm or 1 µrad: both are first order, so only rounding may separate them.
    EXPECT_LT(worst, 1e-9) << machine::info(id).name << ": the map grinds up to " << largest << " µm";
  }
}

} // namespace
