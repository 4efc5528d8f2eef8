// A scene's custom_effects (issue 40) read strictly: every bad declaration refused at its file:line:column with the
// place inside the expression; a law that is not finite at a point refused naming the point and the variables; the
// variables are the contact state of the ground point (checked against the gear's own geometry and the path).
#include "geartopo/effects/custom_effect.hpp"
#include "geartopo/effects/registry.hpp"
#include "geartopo/grinding/flank_deviation.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

using namespace geartopo;

namespace {

const std::string kGear = R"(name: test
gear:
  normal_module_mm: 14
  teeth: 35
  normal_pressure_angle_deg: 20
  helix_angle_deg: 30
  hand: right
  profile_shift: 0.274
  face_width_mm: 150
)";

/// One custom effect named `name` with the parameter lines and expression given (line 10 is `custom_effects:`, 15 deviation_um with two parameters).
std::string with_custom(const std::string& name, const std::string& parameters, const std::string& expression) {
  return kGear + "custom_effects:\n  - name: " + name + "\n    parameters:\n" + parameters + "    deviation_um: " +
         expression + "\n";
}
const std::string kTwo = "      k_um: {value: 1, min: -10, max: 10, unit: um}\n"
                         "      tau_s: {value: 300, min: 30, max: 20000, unit: s}\n";

struct Refusal {
  std::string what;
  int line = 0, column = 0;
  std::string field;
};
Refusal refusal(const std::string& text) {
  try {
    scene::parse_scene(text, "scenes/x.yaml");
  } catch (const InputError& e) {
    return {e.what(), e.line(), e.column(), e.field()};
  }
  return {"(no error)", 0, 0, ""};
}

} // namespace

TEST(CustomEffectsScene, ADeclarationIsReadAsAnEffectOfTheScene) {
  const auto sc = scene::parse_scene(with_custom("warming_read", kTwo, "\"-k_um * (1 - exp(-t_s / tau_s))\""), "mem");
  ASSERT_EQ(sc.custom_effects, std::vector<std::string>{"warming_read"});
  ASSERT_EQ(sc.effects.size(), 1u);
  EXPECT_EQ(sc.effects[0].type, "warming_read");
  EXPECT_EQ(sc.effects[0].values, (std::vector<double>{1.0, 300.0}));
  const auto e = effects::make_effect("warming_read");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->parameters()[1].lo, 30.0);
  EXPECT_EQ(e->parameters()[1].hi, 20000.0);
  EXPECT_NE(std::string(e->explanation()).find("-k_um * (1 - exp(-t_s / tau_s))"), std::string::npos);
  EXPECT_TRUE(effects::is_custom_effect("warming_read"));
  EXPECT_FALSE(effects::is_custom_effect("thermal_drift"));
}

TEST(CustomEffectsScene, ASyntaxErrorIsRefusedAtItsCharacter) {
  // Line 15 is deviation_um; the value's quote stands at column 19, so character k of the expression is at 19 + k.
  const auto r = refusal(with_custom("bad_syntax", kTwo, "\"k_um * (1 - t_s\""));
  EXPECT_EQ(r.line, 15) << r.what;
  EXPECT_EQ(r.field, "custom_effects[0].deviation_um") << r.what;
  EXPECT_EQ(r.column, 19 + 16) << r.what; // the end of the expression: a ')' is missing there
  EXPECT_NE(r.what.find("at character 16 of the expression"), std::string::npos) << r.what;
}

TEST(CustomEffectsScene, AnUnknownVariableOrFunctionIsNamedAtItsCharacter) {
  const auto v = refusal(with_custom("bad_variable", kTwo, "\"k_um * y_mmm\""));
  EXPECT_NE(v.what.find("unknown variable 'y_mmm'"), std::string::npos) << v.what;
  EXPECT_EQ(v.line, 15);
  EXPECT_EQ(v.column, 19 + 8) << v.what;
  EXPECT_NE(v.what.find("at character 8 of the expression"), std::string::npos) << v.what;
  const auto f = refusal(with_custom("bad_function", kTwo, "k_um * erf(t_s)")); // plain scalar: no quote to skip
  EXPECT_NE(f.what.find("unknown function 'erf'"), std::string::npos) << f.what;
  EXPECT_EQ(f.column, 19 + 7) << f.what;
}

TEST(CustomEffectsScene, AParameterWithoutABoundOrUnitIsRefused) {
  const auto r = refusal(with_custom("no_bound", "      k_um: {value: 1, min: -10, unit: um}\n", "k_um"));
  EXPECT_EQ(r.field, "custom_effects[0].parameters.k_um.max") << r.what;
  EXPECT_EQ(r.line, 13) << r.what;
  EXPECT_NE(r.what.find("needs its bounds min and max"), std::string::npos) << r.what;
  EXPECT_NE(refusal(with_custom("no_unit", "      k_um: {value: 1, min: -10, max: 10}\n", "k_um")).what.find("unit"),
            std::string::npos);
  const auto outside = refusal(with_custom("outside", "      k_um: {value: 11, min: -10, max: 10, unit: um}\n", "k_um"));
  EXPECT_EQ(outside.field, "custom_effects[0].parameters.k_um.value") << outside.what;
  const auto as_variable = refusal(with_custom("as_variable", "      t_s: {value: 1, min: -10, max: 10, unit: s}\n", "t_s"));
  EXPECT_NE(as_variable.what.find("is a contact variable"), std::string::npos) << as_variable.what;
}

TEST(CustomEffectsScene, ANameOfTheLibraryOrTwiceOrAnotherLawUnderAKnownNameIsRefused) {
  const auto library = refusal(with_custom("thermal_drift", kTwo, "k_um"));
  EXPECT_EQ(library.field, "custom_effects[0].name") << library.what;
  EXPECT_NE(library.what.find("is an effect of the library"), std::string::npos) << library.what;
  const std::string twice = with_custom("twice", kTwo, "k_um") + "  - name: twice\n    parameters:\n" + kTwo +
                            "    deviation_um: k_um\n";
  EXPECT_NE(refusal(twice).what.find("'twice' is listed twice"), std::string::npos) << refusal(twice).what;
  // The same law again (another scene, values aside) is fine; another law under that name would change effects made
  // with the first, so it is refused.
  EXPECT_NO_THROW(scene::parse_scene(with_custom("kept_law", kTwo, "k_um * tau_s"), "mem"));
  EXPECT_NO_THROW(scene::parse_scene(with_custom("kept_law", kTwo, "k_um * tau_s"), "mem"));
  const auto other = refusal(with_custom("kept_law", kTwo, "k_um / tau_s"));
  EXPECT_NE(other.what.find("with another law"), std::string::npos) << other.what;
  // Listed under effects, a custom name is pointed to custom_effects.
  EXPECT_NE(refusal(kGear + "effects:\n  - type: kept_law\n").what.find("declared under custom_effects"), std::string::npos);
}

TEST(CustomEffectsScene, ANonFiniteValueIsRefusedNamingThePointAndTheVariables) {
  // log(tooth − 1): −∞ on tooth 1, the first point in the check's order.
  const std::string text = with_custom("log_tooth", kTwo, "\"k_um * log(tooth - 1)\"");
  try {
    const workbench::Workbench wb(scene::parse_scene(text, "scenes/x.yaml"));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_EQ(e.line(), 15) << w;
    EXPECT_EQ(e.field(), "custom_effects[0].deviation_um") << w;
    EXPECT_NE(w.find("is not finite at tooth 1, left flank, d = "), std::string::npos) << w;
    EXPECT_NE(w.find("k_um = 1, tau_s = 300, t_s = "), std::string::npos) << w;
    EXPECT_NE(w.find("tooth = 1,"), std::string::npos) << w;
  }
}

TEST(CustomEffectsScene, TheVariablesAreTheContactStateOfTheGroundPoint) {
  // Each variable on its own is the law: the effect's value at a point's generating contact is the variable there,
  // compared with the gear's geometry and the path computed here.
  const std::string vars[] = {"t_s", "stroke", "tooth", "side", "x_mm", "y_mm", "z_mm", "r_mm", "roll_mm", "nx", "ny",
                              "nz", "c_deg", "X_mm", "Y_mm", "Z_mm", "A_deg", "wheel_r_mm", "strokes_since_dressing"};
  std::string params = "      k: {value: 1, min: -10, max: 10, unit: '1'}\n";
  const workbench::Workbench plain(scene::parse_scene(kGear, "mem"));
  const auto& s = plain.setup;
  const grinding::IdealProcess ideal;
  const grinding::FlankDeviation generating(s.flanks(), s.wheel(), s.path(), ideal);
  for (const auto& var : vars) {
    const workbench::Workbench wb(scene::parse_scene(with_custom("var_" + var, params, "k * " + var), "mem"));
    for (const auto flank : {Flank::Left, Flank::Right})
      for (int tooth : {1, 17, 35}) {
        const double xi = 0.5 * (s.ranges().xi_eval_start_mm + s.ranges().xi_eval_end_mm) + 3.0;
        const double z = 100.0;
        const auto c = generating.linear_contact(tooth, flank, xi, z);
        const double got = -1e3 * wb.effects[0]->wheel_radius_error_mm(c.v, c.pp) * s.wheel().normal_per_radial(c.v);
        const auto fp = s.flanks().at(tooth, flank, xi, z);
        const int space = grinding::space_of(tooth, flank, 35);
        double want = 0.0;
        if (var == "t_s") want = s.path().time_at(space, c.pp.z_stroke_mm);
        if (var == "stroke") want = s.path().stroke_index(space);
        if (var == "strokes_since_dressing")
          want = s.path().stroke_index(space) + s.path().stroke_progress(space, c.pp.z_stroke_mm);
        if (var == "tooth") want = tooth;
        if (var == "side") want = flank == Flank::Right ? 1 : -1;
        if (var == "x_mm") want = fp.p.x();
        if (var == "y_mm") want = fp.p.y();
        if (var == "z_mm") want = z;
        if (var == "r_mm") want = std::hypot(fp.p.x(), fp.p.y());
        if (var == "roll_mm") want = std::sqrt(std::pow(std::hypot(fp.p.x(), fp.p.y()), 2) - std::pow(s.geometry().base_diameter_mm() / 2, 2));
        if (var == "nx") want = fp.n.x();
        if (var == "ny") want = fp.n.y();
        if (var == "nz") want = fp.n.z();
        if (var == "c_deg") want = c.pp.q.c * 180.0 / std::numbers::pi;
        if (var == "X_mm") want = s.setting().centre_distance_mm;
        if (var == "Y_mm") want = s.setting().axial_position_mm;
        if (var == "Z_mm") want = c.pp.z_stroke_mm;
        if (var == "A_deg") want = s.setting().tilt_rad * 180.0 / std::numbers::pi;
        if (var == "wheel_r_mm") want = s.wheel().radius(c.v);
        // 1e-6 of the value's scale: the contact map is a spline through 0.025 mm samples of the contact lines.
        const double scale = std::max(1.0, std::abs(want));
        EXPECT_NEAR(got, want, 1e-5 * scale) << var << " at tooth " << tooth << (flank == Flank::Left ? " left" : " right");
      }
  }
}
