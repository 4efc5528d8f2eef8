// The identified explanation as diagnose writes it into scene_with_effect.yaml and the scene reader reads it back:
// values, the fit's standard uncertainties (σ̂² = RSS/ν already contains χ²/ν: the Birge ratio is reported, not applied
// again; docs/diagnosis.md), at most the allowed range, and the fit's correlation at the fitted values' slots — the
// expected numbers written here from the candidate and the parameters' documented ranges, not from the code.
#include "geartopo/diagnosis/identified_effects.hpp"
#include "geartopo/diagnosis/scene_writer.hpp"
#include "geartopo/scene/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace geartopo;

namespace {

const std::string kIdentifiedSceneText = R"(gear:
  normal_module_mm: 4
  teeth: 20
  normal_pressure_angle_deg: 20
  helix_angle_deg: 20
  profile_shift: 0
  face_width_mm: 30
)";

// A pair fitted jointly: thermal drift (x_growth, τ fitted; z_growth held) and wheel wear (wear fitted; the dressing
// interval a set-up count), χ² = 4 ν: Birge ratio 2, already in the fit's σ.
diagnosis::Diagnosis identified_pair() {
  diagnosis::Candidate c;
  c.effects = {{"thermal_drift", {23.0123456, 0.0, 94.4}}, {"wheel_wear", {0.0512, 0.0}}};
  c.parameters = {{{"x_growth_um", 23.0123456, 4.1, true}, {"z_growth_um", 0.0, 0.0, false},
                   {"time_constant_s", 94.4, 48.25, true}},
                  {{"wear_um_per_stroke", 0.0512, 0.0031, true}, {"dressing_interval_strokes", 0.0, 0.0, false}}};
  c.correlation.resize(3, 3);
  c.correlation << 1.0, 0.8512, -0.25, 0.8512, 1.0, 0.125, -0.25, 0.125, 1.0;
  diagnosis::Diagnosis d;
  d.chosen = c;
  d.chi2_after = 400.0;
  d.chi2_dof = 100.0;
  return d;
}

} // namespace

TEST(IdentifiedEffects, TheFitsUncertaintiesAndCorrelationAtTheFittedSlots) {
  const auto d = identified_pair();
  const auto id = diagnosis::identified_effects(d, *d.chosen);
  EXPECT_DOUBLE_EQ(id.birge_ratio, 2.0);
  ASSERT_EQ(id.uncertainties.size(), 2u);
  EXPECT_EQ(id.uncertainties[0], (std::vector<double>{4.1, 0.0, 48.25}));
  EXPECT_EQ(id.uncertainties[1], (std::vector<double>{0.0031, 0.0}));
  // Values x_growth 0, z_growth 1, τ 2, wear 3, dressing 4; fitted: 0, 2, 3.
  Eigen::MatrixXd expected = Eigen::MatrixXd::Identity(5, 5);
  expected(0, 2) = expected(2, 0) = 0.8512;
  expected(0, 3) = expected(3, 0) = -0.25;
  expected(2, 3) = expected(3, 2) = 0.125;
  EXPECT_EQ(id.correlation, expected);
  // A residual within its noise (χ² < ν) does not narrow them.
  auto quiet = d;
  quiet.chi2_after = 50.0;
  EXPECT_DOUBLE_EQ(diagnosis::identified_effects(quiet, *quiet.chosen).birge_ratio, 1.0);
}

// An undetermined direction of a fit (two teeth: amplitude against time constant, docs/tutorial.md §4) can have a σ
// far beyond the parameter's allowed range; written as is, the scene reader refused diagnose's own
// scene_with_effect.yaml. It is capped at the range's width (docs/scene-format.md: x_growth_um [-500, 500],
// time_constant_s [10, 1e6]), and the scene reads back.
TEST(IdentifiedEffects, AnUndeterminedValueIsCappedAtItsRangeAndTheSceneReadsBack) {
  auto d = identified_pair();
  d.chosen->parameters[0][0].uncertainty = 4.9e4; // µm
  d.chosen->parameters[0][2].uncertainty = 8.2e7; // s
  const auto id = diagnosis::identified_effects(d, *d.chosen);
  EXPECT_EQ(id.uncertainties[0], (std::vector<double>{1000.0, 0.0, 1e6 - 10.0}));
  const std::string text =
      diagnosis::scene_with_effects(kIdentifiedSceneText, id.effects, {"found", "found too"}, id.uncertainties, id.correlation);
  const auto back = scene::parse_scene(text, "scene_with_effect.yaml");
  ASSERT_EQ(back.effect_uncertainties.size(), 2u);
  EXPECT_EQ(back.effect_uncertainties[0][0], 1000.0);
  EXPECT_EQ(back.effect_uncertainties[0][2], 999990.0);
}

// What diagnose writes (scene_with_effects, 6 significant digits) is read back equal to that precision.
TEST(IdentifiedEffects, WrittenIntoTheSceneAndReadBackEqual) {
  const auto d = identified_pair();
  const auto id = diagnosis::identified_effects(d, *d.chosen);
  const std::string text =
      diagnosis::scene_with_effects(kIdentifiedSceneText, id.effects, {"found", "found too"}, id.uncertainties, id.correlation);
  EXPECT_NE(text.find("    uncertainty: {x_growth_um: 4.1, time_constant_s: 48.25}\n"), std::string::npos) << text;
  EXPECT_NE(text.find("    correlation: [[x_growth_um, time_constant_s, 0.8512], [x_growth_um, wheel_wear.wear_um_per_stroke, "
                      "-0.25], [time_constant_s, wheel_wear.wear_um_per_stroke, 0.125]]\n"),
            std::string::npos)
      << text;
  const auto back = scene::parse_scene(text, "scene_with_effect.yaml");
  ASSERT_EQ(back.effects.size(), 2u);
  const auto near6 = [](double a, double b) { return std::abs(a - b) <= 5e-6 * std::max(std::abs(a), 1e-300); };
  for (size_t e = 0; e < 2; ++e) {
    EXPECT_EQ(back.effects[e].type, id.effects[e].type);
    for (size_t v = 0; v < id.effects[e].values.size(); ++v) {
      EXPECT_TRUE(near6(back.effects[e].values[v], id.effects[e].values[v]) || back.effects[e].values[v] == id.effects[e].values[v])
          << e << " " << v << ": " << back.effects[e].values[v];
      EXPECT_TRUE(near6(back.effect_uncertainties[e][v], id.uncertainties[e][v]) ||
                  back.effect_uncertainties[e][v] == id.uncertainties[e][v])
          << e << " " << v;
    }
  }
  EXPECT_TRUE(back.effect_correlation.isApprox(id.correlation, 1e-6)) << back.effect_correlation;
}

// A choice whose single values are not determined goes into the scene as its posterior's value sets
// (Diagnosis::draws; docs/diagnosis.md, "What the data determine goes into the scene"): no Gaussian uncertainty and no
// correlation of its values — the fit's σ of an open value spans far beyond anything physical — and the sets read back
// equal to the 6 written digits, every value of a set in its effect's parameter order.
TEST(IdentifiedEffects, OpenValuesGoIntoTheSceneAsThePosteriorsValueSets) {
  auto d = identified_pair();
  diagnosis::PosteriorDraws draws;
  Eigen::MatrixXd drift(3, 3), wear(3, 2);
  drift << 8.1234567, 0.0, 412.5, 12.25, 0.0, 977.0, 31.5, 0.0, 3012.0;
  wear << 0.041, 0.0, 0.0512, 0.0, 0.0633, 0.0;
  draws.values = {drift, wear};
  draws.grid_points = 64;
  d.draws = draws;
  const auto id = diagnosis::identified_effects(d, *d.chosen);
  ASSERT_EQ(id.draws.size(), 2u);
  EXPECT_EQ(id.uncertainties[0], (std::vector<double>{0.0, 0.0, 0.0}));
  EXPECT_EQ(id.uncertainties[1], (std::vector<double>{0.0, 0.0}));
  EXPECT_TRUE(id.correlation.isIdentity(0.0)) << id.correlation;
  const std::string text = diagnosis::scene_with_effects(kIdentifiedSceneText, id.effects, {"found", "found too"},
                                                         id.uncertainties, id.correlation, id.draws);
  EXPECT_EQ(text.find("uncertainty:"), std::string::npos) << text;
  EXPECT_EQ(text.find("correlation:"), std::string::npos) << text;
  // The fitted values only: z_growth is held, the dressing interval a set-up count.
  EXPECT_NE(text.find("      keys: [x_growth_um, time_constant_s]\n      sets:\n        - [8.12346, 412.5]\n"), std::string::npos)
      << text;
  const auto back = scene::parse_scene(text, "scene_with_effect.yaml");
  ASSERT_EQ(back.effect_draws.size(), 2u);
  EXPECT_TRUE(back.effect_draws[0].isApprox(drift, 1e-6)) << back.effect_draws[0];
  EXPECT_TRUE(back.effect_draws[1].isApprox(wear, 1e-6)) << back.effect_draws[1];
  // Another candidate than the one drawn keeps the fit's Gaussian.
  auto other = *d.chosen;
  other.effects[0].values[0] = 5.0;
  EXPECT_TRUE(diagnosis::identified_effects(d, other).draws.empty());
  EXPECT_EQ(diagnosis::identified_effects(d, other).uncertainties[0][0], 4.1);
}
