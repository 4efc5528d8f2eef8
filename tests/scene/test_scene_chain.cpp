// The machine's kinematic chain in a scene (docs/scene-format.md, `machine.chain`): a preset by name, an inline
// description, a chain file; the scene's strokes applied to it; bad chains located at the axis' field.
#include "geartopo/scene/scene.hpp"

#include "../chain_scene_fixture.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <unistd.h>

using namespace geartopo;

namespace scene_chain_test { // named: the suite is one unity build with test_scene.cpp

// The CAFXZY written out as its description (machine/kinematic_chain.cpp's preset, docs/machine-model.md §9).
const std::string kCafxzyInline = R"(machine:
  chain:
    name: CAFXZY
    workpiece:
      - {name: C, kind: rotary, direction: [0, 0, 1], offset_mm: [0, 0, 150]}
      - {name: A, kind: rotary, direction: [1, 0, 0], stroke_deg: [-45, 45]}
    tool:
      - {name: X, kind: linear, direction: [1, 0, 0], stroke_mm: [0, 900]}
      - {name: Z, kind: linear, direction: [0, 0, 1], stroke_mm: [-300, 700]}
      - {name: Y, kind: linear, direction: [0, 1, 0], stroke_mm: [-500, 500]}
)";

std::string with_replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return pos == std::string::npos ? text : text.replace(pos, from.size(), to);
}

std::string chain_error_of(const std::string& text, const std::string& source = "scenes/x.yaml") {
  try {
    scene::parse_scene(text, source);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

} // namespace scene_chain_test

using namespace scene_chain_test;

TEST(SceneChain, AbsentChainIsTheCfxzayWithTheSeedStrokes) {
  const auto sc = scene::parse_scene(chain_fixture::kGear, "mem");
  EXPECT_EQ(sc.machine.chain, &machine::cfxzay());
  EXPECT_TRUE(sc.machine.chain->is_setting_chain());
  EXPECT_EQ(sc.machine.strokes.a_deg.max, 45.0);
  EXPECT_EQ(sc.machine.strokes.z_mm.max, 800.0);
  const auto named = scene::parse_scene(chain_fixture::kGear + "machine:\n  chain: CFXZAY\n", "mem");
  EXPECT_EQ(named.machine.chain, &machine::cfxzay());
}

TEST(SceneChain, APresetByNameBringsItsStrokesAndTheSceneOverridesThem) {
  const auto sc = scene::parse_scene(chain_fixture::kGear + "machine:\n  chain: CAFXZY\n", "mem");
  EXPECT_EQ(sc.machine.chain, machine::chain_preset("CAFXZY"));
  EXPECT_FALSE(sc.machine.chain->is_setting_chain());
  EXPECT_EQ(sc.machine.strokes.y_mm.min, -500.0);
  EXPECT_EQ(sc.machine.strokes.z_mm.min, -300.0);
  EXPECT_EQ(sc.machine.strokes.z_mm.max, 700.0);
  // Face width 40 mm centred in Z [−300, 700]: datum face at 200 − 20.
  EXPECT_EQ(sc.machine.datum_face_z_mm, 180.0);

  const auto narrowed = scene::parse_scene(chain_fixture::kGear + "machine:\n  chain: CAFXZY\n  strokes:\n    y_mm: [-400, 300]\n"
                                                   "    a_deg: [-30, 30]\n", "mem");
  const auto& chain = *narrowed.machine.chain;
  EXPECT_EQ(chain.name(), "CAFXZY");
  EXPECT_EQ(chain.axis(machine::Axis::Y).stroke->min, -400.0);
  EXPECT_EQ(chain.axis(machine::Axis::Y).stroke->max, 300.0);
  EXPECT_NEAR(chain.axis(machine::Axis::A).stroke->max, 30.0 * std::numbers::pi / 180.0, 1e-15);
  EXPECT_EQ(chain.axis(machine::Axis::Z).stroke->min, -300.0); // not given: the preset's
  EXPECT_EQ(narrowed.machine.strokes.y_mm.min, -400.0);
  EXPECT_EQ(narrowed.machine.strokes.a_deg.max, 30.0);
}

TEST(SceneChain, AnInlineDescriptionOfThePresetIsThePreset) {
  // make_chain keeps one chain per description: the scene's reading of every field is the preset's, field by field.
  const auto sc = scene::parse_scene(chain_fixture::kGear + kCafxzyInline, "mem");
  EXPECT_EQ(sc.machine.chain, machine::chain_preset("CAFXZY"));
}

TEST(SceneChain, BadChainsAreLocatedAtTheAxisField) {
  const std::string text = chain_fixture::kGear + kCafxzyInline;
  // Lines: gear 1–8, machine 9, chain 10, name 11, workpiece 12, C 13, A 14, tool 15, X 16, Z 17, Y 18.
  const auto dup = chain_error_of(with_replaced(text, "{name: Y,", "{name: X,"));
  EXPECT_NE(dup.find("scenes/x.yaml:18:"), std::string::npos) << dup;
  EXPECT_NE(dup.find("machine.chain.tool[2].name: axis X is named twice"), std::string::npos) << dup;
  const auto zero = chain_error_of(with_replaced(text, "direction: [0, 1, 0]", "direction: [0, 0, 0]"));
  EXPECT_NE(zero.find(":18:"), std::string::npos) << zero;
  EXPECT_NE(zero.find("machine.chain.tool[2].direction: axis Y: the direction has zero length"), std::string::npos) << zero;
  const auto no_stroke = chain_error_of(with_replaced(text, ", stroke_deg: [-45, 45]", ""));
  EXPECT_NE(no_stroke.find(":14:"), std::string::npos) << no_stroke;
  EXPECT_NE(no_stroke.find("machine.chain.workpiece[1]"), std::string::npos) << no_stroke;
  EXPECT_NE(no_stroke.find("needs a stroke"), std::string::npos) << no_stroke;
  const auto four = chain_error_of(with_replaced(text, "      - {name: Z, kind: linear, direction: [0, 0, 1], stroke_mm: [-300, 700]}\n", ""));
  EXPECT_NE(four.find(":11:"), std::string::npos) << four; // the chain's map (its first key's line)
  EXPECT_NE(four.find("machine.chain: a profile grinder's chain has five moving axes"), std::string::npos) << four;
  const auto unit = chain_error_of(with_replaced(text, "stroke_deg: [-45, 45]", "stroke_mm: [-45, 45]"));
  EXPECT_NE(unit.find("machine.chain.workpiece[1].stroke_mm: a rotary axis' stroke is in deg"), std::string::npos) << unit;
  const auto kind = chain_error_of(with_replaced(text, "kind: linear, direction: [1, 0, 0]", "kind: slide, direction: [1, 0, 0]"));
  EXPECT_NE(kind.find(":16:"), std::string::npos) << kind;
  EXPECT_NE(kind.find("machine.chain.tool[0].kind: 'slide' is not one of: linear, rotary"), std::string::npos) << kind;
  const auto preset = chain_error_of(chain_fixture::kGear + "machine:\n  chain: CXYZAB\n");
  EXPECT_NE(preset.find(":10:10: machine.chain: 'CXYZAB' is not a preset chain (CFXZAY, CAFXZY, CXFZAY)"), std::string::npos)
      << preset;
  const auto stroke_key = chain_error_of(chain_fixture::kGear + "machine:\n  chain: CAFXZY\n  strokes:\n    u_mm: [0, 1]\n");
  EXPECT_NE(stroke_key.find("machine.strokes.u_mm"), std::string::npos) << stroke_key;
}

TEST(SceneChain, AChainFileIsReadBesideTheSceneAndItsErrorsLocatedInIt) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_chain_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "machine");
  std::string description = kCafxzyInline.substr(kCafxzyInline.find("    name:"));
  // The file holds the chain's map at its top level: strip the four spaces of its place in the scene.
  std::string file;
  for (std::size_t pos = 0; pos < description.size();) {
    const auto end = description.find('\n', pos);
    file += description.substr(pos + 4, end - pos - 4) + "\n";
    pos = end + 1;
  }
  std::ofstream(dir / "machine" / "cafxzy.yaml") << file;
  const auto scene_file = dir / "s.yaml";
  std::ofstream(scene_file) << chain_fixture::kGear << "machine:\n  chain_file: machine/cafxzy.yaml\n";
  EXPECT_EQ(scene::load_scene(scene_file).machine.chain, machine::chain_preset("CAFXZY"));

  std::ofstream(dir / "machine" / "cafxzy.yaml") << with_replaced(file, "[0, 0, 150]", "[0, nan, 150]");
  try {
    scene::load_scene(scene_file);
    FAIL() << "accepted a NaN offset";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "machine" / "cafxzy.yaml").string());
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "workpiece[0].offset_mm");
  }
  const auto missing = chain_error_of(chain_fixture::kGear + "machine:\n  chain_file: machine/none.yaml\n", scene_file.string());
  EXPECT_NE(missing.find("machine.chain_file: "), std::string::npos) << missing;
  EXPECT_NE(missing.find("none.yaml"), std::string::npos) << missing;
  const auto both = chain_error_of(chain_fixture::kGear + "machine:\n  chain: CAFXZY\n  chain_file: machine/cafxzy.yaml\n");
  EXPECT_NE(both.find("machine.chain_file: give the chain once"), std::string::npos) << both;
  std::filesystem::remove_all(dir);
}

// Repeatability and resolution are per axis of the chain, by its letters (the stroke scatter and the rounding act on
// its axes): on the CAFXZY described with its radial slide called U and its swivel B (pose order Y, Z, U, B, C) the
// keys are u_um and b_mdeg, read into U's and B's slots (R↑ = 4 s), and x_um is no key of that chain.
TEST(SceneChain, RepeatabilityAndResolutionTakeTheChainsLetters) {
  const std::string renamed = with_replaced(with_replaced(kCafxzyInline, "{name: X,", "{name: U,"), "{name: A,", "{name: B,");
  const auto sc = scene::parse_scene(chain_fixture::kGear + renamed +
                                         "  repeatability: {u_um: 4, b_mdeg: 8, y_um: 0, z_um: 0, c_mdeg: 0}\n"
                                         "  resolution: {u_um: 0.5, b_mdeg: 0.25}\n",
                                     "mem");
  const auto& chain = *sc.machine.chain;
  ASSERT_EQ(chain.axis_name(machine::Axis::Z), "U"); // pose slot 2: the third linear letter in ISO 841 order
  ASSERT_EQ(chain.axis_name(machine::Axis::A), "B");
  const auto& u = sc.machine.uncertainty;
  EXPECT_NEAR(u.repeatability(2), 1e-3, 1e-15);                                // mm: 4 µm / 4
  EXPECT_NEAR(u.repeatability(3), 2e-3 * std::numbers::pi / 180.0, 1e-15);    // rad: 8 mdeg / 4
  EXPECT_EQ(u.repeatability(0), 0.0);
  EXPECT_NEAR(u.resolution(2), 0.5e-3, 1e-15);
  EXPECT_NEAR(u.resolution(3), 0.25e-3 * std::numbers::pi / 180.0, 1e-15);
  const auto e = chain_error_of(chain_fixture::kGear + renamed + "  repeatability: {x_um: 4}\n");
  EXPECT_NE(e.find("machine.repeatability.x_um"), std::string::npos) << e;
}
