// Scene files: the default scene, and every kind of bad input located at file:line:column with its field.
#include "geartopo/scene/scene.hpp"
#include "geartopo/workbench/workbench.hpp"

#include <gtest/gtest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <unistd.h>

using namespace geartopo;

namespace {

const std::string kGood = R"(name: test
gear:
  normal_module_mm: 14
  teeth: 35
  normal_pressure_angle_deg: 20
  helix_angle_deg: 30
  hand: right
  profile_shift: 0.274
  face_width_mm: 150
)";

// Replaces the first line containing `key:` by `replacement` (or deletes it when empty).
std::string with_line(const std::string& text, const std::string& key, const std::string& replacement) {
  const auto pos = text.find(key + ":");
  EXPECT_NE(pos, std::string::npos) << key;
  const auto start = text.rfind('\n', pos) + 1;
  const auto end = text.find('\n', pos);
  return text.substr(0, start) + replacement + (replacement.empty() ? "" : "\n") + text.substr(end + 1);
}

std::string error_of_source(const std::string& text, const std::string& source) {
  try {
    scene::parse_scene(text, source);
  } catch (const geartopo::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string error_of(const std::string& text) {
  try {
    scene::parse_scene(text, "scenes/x.yaml");
  } catch (const geartopo::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

} // namespace

TEST(Scene, DefaultSceneLoads) {
  const auto sc = scene::load_scene(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml");
  EXPECT_EQ(sc.gear.teeth, 35);
  EXPECT_DOUBLE_EQ(sc.gear.normal_module_mm, 14.0);
  EXPECT_NEAR(sc.gear.helix_angle_rad, 30.0 * std::numbers::pi / 180, 1e-15);
  EXPECT_EQ(sc.gear.hand(), gears::Hand::Right);
  EXPECT_DOUBLE_EQ(sc.gear.profile_shift, 0.274);
  EXPECT_DOUBLE_EQ(sc.gear.face_width_mm, 150.0);
  // The assumed tip and root follow the conventional formulas to the 0.1 µm written in the file.
  EXPECT_NEAR(sc.gear.tip_diameter_mm, gears::conventional_tip_diameter(sc.gear), 1e-4);
  EXPECT_NEAR(sc.gear.root_diameter_mm, gears::conventional_root_diameter(sc.gear), 1e-4);
  EXPECT_EQ(sc.assumed, (std::vector<std::string>{"face_width_mm", "tip_diameter_mm", "root_diameter_mm"}));
}

TEST(Scene, AbsentTipAndRootTakeConventionalValues) {
  const auto sc = scene::parse_scene(kGood, "mem");
  EXPECT_DOUBLE_EQ(sc.gear.tip_diameter_mm, gears::conventional_tip_diameter(sc.gear));
  EXPECT_EQ(sc.defaulted, (std::vector<std::string>{"tip_diameter_mm", "root_diameter_mm"}));
}

TEST(Scene, OutOfRangeValueIsLocated) {
  // helix_angle_deg is on line 6, its value at column 20.
  EXPECT_EQ(error_of(with_line(kGood, "helix_angle_deg", "  helix_angle_deg: 95")),
            "scenes/x.yaml:6:20: gear.helix_angle_deg: 95 is outside [-45, 45]");
}

TEST(Scene, UnknownKeyIsLocatedAtTheKey) {
  const auto msg = error_of(kGood + "  helix_angel_deg: 3\n");
  EXPECT_EQ(msg.rfind("scenes/x.yaml:10:3: gear.helix_angel_deg: unknown key", 0), 0u) << msg;
  EXPECT_NE(error_of(kGood + "machnie: {}\n").find("scenes/x.yaml:10:1: machnie: unknown key"), std::string::npos);
}

TEST(Scene, MissingFieldIsLocatedAtItsSection) {
  EXPECT_EQ(error_of(with_line(kGood, "teeth", "")),
            "scenes/x.yaml:3:3: gear.teeth: missing (a whole number in [5, 10000])");
  EXPECT_EQ(error_of("name: x\n"), "scenes/x.yaml:1:1: gear: missing (a map)");
}

// Issue 44: a misspelled required key was reported as the required key missing ("gear.normal_module_mm: missing"),
// which hides the user's own line. A key no reader asked for that looks like the missing one (holds it or is held by
// it, or a few edits away) is reported where it stands, as unknown, with the keys known and the one it should be; an
// unrelated missing key is still "missing".
TEST(Scene, AMisspelledRequiredKeyIsNamedAsUnknownWhereItStands) {
  const auto msg = error_of(with_line(kGood, "normal_module_mm", "  module_mm: 14"));
  EXPECT_EQ(msg.rfind("scenes/x.yaml:3:3: gear.module_mm: unknown key (known here, among others: ", 0), 0u) << msg;
  EXPECT_NE(msg.find("did you mean normal_module_mm? It is missing (a number in "), std::string::npos) << msg;
  const auto typo = error_of(with_line(kGood, "teeth", "  teth: 35"));
  EXPECT_EQ(typo.rfind("scenes/x.yaml:4:3: gear.teth: unknown key (known here, among others: ", 0), 0u) << typo;
  EXPECT_NE(typo.find("normal_module_mm, teeth); did you mean teeth?"), std::string::npos) << typo;
  EXPECT_EQ(error_of(with_line(kGood, "teeth", "  colour: red")),
            "scenes/x.yaml:3:3: gear.teeth: missing (a whole number in [5, 10000])");
}

TEST(Scene, WrongTypesAreNamed) {
  EXPECT_EQ(error_of(with_line(kGood, "teeth", "  teeth: 35.5")), "scenes/x.yaml:4:10: gear.teeth: '35.5' is not a whole number");
  EXPECT_EQ(error_of(with_line(kGood, "teeth", "  teeth: many")), "scenes/x.yaml:4:10: gear.teeth: 'many' is not a whole number");
  EXPECT_EQ(error_of(with_line(kGood, "profile_shift", "  profile_shift: [1, 2]")),
            "scenes/x.yaml:8:18: gear.profile_shift: a list is not a number");
  EXPECT_EQ(error_of(with_line(kGood, "profile_shift", "  profile_shift: .nan")),
            "scenes/x.yaml:8:18: gear.profile_shift: '.nan' is not a number");
  EXPECT_EQ(error_of(with_line(kGood, "hand", "  hand: sinister")),
            "scenes/x.yaml:7:9: gear.hand: 'sinister' is not one of: right, left, spur");
  EXPECT_EQ(error_of("gear: 3\n"), "scenes/x.yaml:1:7: gear: expected a map of keys, found '3'");
}

TEST(Scene, DegenerateGearsAreLocatedAtTheirField) {
  EXPECT_EQ(error_of(with_line(kGood, "normal_module_mm", "  normal_module_mm: 0")),
            "scenes/x.yaml:3:21: gear.normal_module_mm: 0 is outside [0.001, 100]: below 0.001 mm (1 µm) a dimension is smaller than the µm deviations geartopo computes: no gear, wheel or probe is that small");
  EXPECT_EQ(error_of(with_line(kGood, "teeth", "  teeth: 4")), "scenes/x.yaml:4:10: gear.teeth: 4 is outside [5, 10000]");
  const auto at45 = error_of(with_line(kGood, "helix_angle_deg", "  helix_angle_deg: 45"));
  EXPECT_EQ(at45.rfind("scenes/x.yaml:6:20: gear.helix_angle_deg: ", 0), 0u) << at45;
  // Undercut: a spur pinion with 8 teeth and no shift.
  std::string undercut = with_line(kGood, "teeth", "  teeth: 8");
  undercut = with_line(undercut, "helix_angle_deg", "  helix_angle_deg: 0");
  undercut = with_line(undercut, "hand", "  hand: spur");
  undercut = with_line(undercut, "profile_shift", "  profile_shift: 0");
  const auto uc = error_of(undercut);
  EXPECT_EQ(uc.rfind("scenes/x.yaml:8:18: gear.profile_shift: x = 0 is below x_min", 0), 0u) << uc;
  EXPECT_NE(uc.find("undercut"), std::string::npos);
  // Pointed tip: a tip diameter far above the conventional 601 mm.
  const auto pt = error_of(kGood + "  tip_diameter_mm: 640\n");
  EXPECT_EQ(pt.rfind("scenes/x.yaml:10:20: gear.tip_diameter_mm: ", 0), 0u) << pt;
  EXPECT_NE(pt.find("pointed-tip"), std::string::npos);
}

TEST(Scene, HandMustAgreeWithTheSignOfTheHelixAngle) {
  const auto msg = error_of(with_line(kGood, "hand", "  hand: left"));
  EXPECT_EQ(msg.rfind("scenes/x.yaml:7:9: gear.hand: 'left' contradicts helix_angle_deg = 30", 0), 0u) << msg;
  const auto sc = scene::parse_scene(with_line(with_line(kGood, "hand", "  hand: left"), "helix_angle_deg",
                                               "  helix_angle_deg: -30"), "mem");
  EXPECT_EQ(sc.gear.hand(), gears::Hand::Left);
}

TEST(Scene, SyntaxDuplicatesAndEmptyFiles) {
  const auto syn = error_of("gear: [1, 2\n");
  EXPECT_EQ(syn.rfind("scenes/x.yaml:", 0), 0u);
  EXPECT_NE(syn.find("YAML syntax error"), std::string::npos) << syn;
  EXPECT_EQ(error_of(kGood + "  teeth: 36\n"), "scenes/x.yaml:10:3: gear.teeth: duplicate key");
  EXPECT_EQ(error_of(""), "scenes/x.yaml: empty scene (a 'gear' map is needed)");
  EXPECT_EQ(error_of(kGood + "  assumed: [tip_diameter_mm]\n"),
            "scenes/x.yaml:10:13: gear.assumed: 'tip_diameter_mm' is not a key given in this gear section");
}

// Issue 30: a denormal or tiny dimension passed a bare "> 0"; every positive length of a part is at least 1 µm (the
// unit of the deviations geartopo computes), and the refusal names that bound and why.
TEST(Scene, TinyAndDenormalDimensionsAreRefusedNamingTheBound) {
  const std::string bound = "is outside [0.001, 5000]" + std::string(
      ": below 0.001 mm (1 µm) a dimension is smaller than the µm deviations geartopo computes");
  EXPECT_EQ(error_of(with_line(kGood, "face_width_mm", "  face_width_mm: 1e-320")).rfind(
                "scenes/x.yaml:9:18: gear.face_width_mm: 1e-320 " + bound, 0), 0u)
      << error_of(with_line(kGood, "face_width_mm", "  face_width_mm: 1e-320"));
  EXPECT_EQ(error_of(with_line(kGood, "face_width_mm", "  face_width_mm: 0.0009")).rfind(
                "scenes/x.yaml:9:18: gear.face_width_mm: 0.0009 " + bound, 0), 0u);
  EXPECT_NE(error_of(with_line(kGood, "normal_module_mm", "  normal_module_mm: 4.9e-324")).find(
                "scenes/x.yaml:3:21: gear.normal_module_mm: 4.9e-324 is outside [0.001, 100]: below 0.001 mm"),
            std::string::npos);
  EXPECT_NE(error_of(kGood + "  root_diameter_mm: 1e-310\n").find("scenes/x.yaml:10:21: gear.root_diameter_mm: 1e-310 is "
                                                                "outside [0.001, 50000]: below 0.001 mm"),
            std::string::npos);
  // Above the bound the number is a length again and the gear's own rules judge it (here: the root circle).
  EXPECT_EQ(error_of(kGood + "  root_diameter_mm: 0.001\n").find("below 0.001 mm"), std::string::npos);
}

// Issue 30: lists refuse a duplicate at the item, in the words of `--teeth 1,1`.
TEST(Scene, ListsRefuseDuplicatesAtTheItem) {
  // "  teeth: [1, 2, 1]": the second 1 is at column 17.
  EXPECT_EQ(error_of(kGood + "measurement:\n  teeth: [1, 2, 1]\n"),
            "scenes/x.yaml:11:17: measurement.teeth: tooth 1 is listed twice");
  EXPECT_EQ(error_of(kGood + "measurement:\n  teeth:\n    - 3\n    - 3\n"),
            "scenes/x.yaml:13:7: measurement.teeth: tooth 3 is listed twice");
  EXPECT_EQ(error_of(kGood + "  assumed: [face_width_mm, face_width_mm]\n"),
            "scenes/x.yaml:10:28: gear.assumed: 'face_width_mm' is listed twice");
  const auto sc = scene::parse_scene(kGood + "measurement:\n  teeth: [1, 18]\n", "mem");
  EXPECT_EQ(sc.grid.teeth, (std::vector<int>{1, 18}));
}

// Issue 30: a YAML alias gave the wheel the gear's module (14 mm). The form wheel's rim carries the tooth space's
// profile, h = (d_a − d_f)/2 deep, and needs a body at least as deep again: D_w > 4h, checked when the scene is read.
TEST(Scene, AWheelTooSmallToCarryTheToothSpaceIsRefusedOnReading) {
  const std::string text = with_line(kGood, "normal_module_mm", "  normal_module_mm: &m 14") + "wheel:\n  outer_diameter_mm: *m\n";
  const auto sc = scene::parse_scene(kGood, "mem");
  const gears::GearGeometry g(sc.gear);
  const double h = 0.5 * (g.tip_diameter_mm() - g.root_diameter_mm());
  EXPECT_GT(h, 30.0); // about 2.25 m_n: the 14 mm wheel is less than half the tooth depth in radius
  const auto msg = error_of(text);
  EXPECT_EQ(msg.rfind("scenes/x.yaml:11:3: ", 0), 0u) << msg; // at the key: the alias's own mark is its anchor's (line 3)
  EXPECT_NE(msg.find("wheel.outer_diameter_mm: 14 mm is too small for this gear"), std::string::npos) << msg;
  EXPECT_NE(msg.find(fmt::format("must exceed 4h = {:.3f} mm", 4.0 * h)), std::string::npos) << msg;
  // Just above 4h the scene reads; the default (no wheel given) is left to the workbench, which picks one that fits.
  EXPECT_NO_THROW(scene::parse_scene(kGood + fmt::format("wheel:\n  outer_diameter_mm: {}\n", 4.0 * h + 0.01), "mem"));
}

TEST(Scene, MissingFileNamesTheFile) {
  try {
    scene::load_scene("/nonexistent/scene.yaml");
    FAIL();
  } catch (const geartopo::InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/scene.yaml: cannot open the scene file: it does not exist");
  }
}

// ---- machine, wheel, process and measurement sections ----

namespace {
const std::string kDefault = std::string(GEARTOPO_SOURCE_DIR) + "/scenes/skmc1200w-mn14-z35.yaml";

std::string default_text() {
  std::ifstream in(kDefault);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Parses text as if it were the default scene (relative table paths resolve against scenes/).
/// The error of reading `text` as the default scene and building what it describes (workbench: the set-up's fit to
/// the machine is checked there), or "(no error)".
std::string error_as_default(const std::string& text) {
  try {
    const workbench::Workbench wb(scene::parse_scene(text, kDefault));
  } catch (const geartopo::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}
} // namespace

TEST(SceneMachine, DefaultMachineHasEveryTableAndConstant) {
  const auto sc = scene::load_scene(kDefault);
  EXPECT_EQ(sc.machine.table_files.size(), 5u);
  EXPECT_EQ(sc.machine.sources.size(), 30u + 8u); // 30 motion components from tables + 8 constants
  EXPECT_DOUBLE_EQ(sc.machine.datum_face_z_mm, 300.0);
  EXPECT_DOUBLE_EQ(sc.wheel.outer_diameter_mm, 350.0);
  EXPECT_EQ(sc.grid.rows, 7);
  EXPECT_EQ(sc.grid.cols, 9);
  EXPECT_NO_THROW(static_cast<void>(sc.machine.model()));
}

TEST(SceneMachine, BadMachineDataIsLocated) {
  const std::string text = default_text();
  const auto unknown = error_as_default(replace(text, "S_xy_urad: 25", "S_xx_urad: 25"));
  EXPECT_NE(unknown.find("machine.constants.S_xx_urad: 'S_xx' is not an error component"), std::string::npos) << unknown;
  const auto unit = error_as_default(replace(text, "S_xy_urad: 25", "S_xy_um: 25"));
  EXPECT_NE(unit.find("machine.constants.S_xy_um: "), std::string::npos) << unit;
  const auto dup = error_as_default(replace(text, "S_xy_urad: 25", "S_xy_urad: 25\n    delta_xx_um: 2"));
  EXPECT_NE(dup.find("delta_xx"), std::string::npos) << dup;
  const auto missing = error_as_default(replace(text, "machine/z_axis.csv", "machine/none.csv"));
  EXPECT_NE(missing.find("none.csv"), std::string::npos) << missing;
  const auto stroke = error_as_default(replace(text, "datum_face_z_mm: 300", "datum_face_z_mm: 700"));
  EXPECT_NE(stroke.find(":31:20: machine.datum_face_z_mm: the strokes run from Z = "), std::string::npos) << stroke;
}

TEST(SceneMachine, BadErrorTableIsLocatedInTheTableFile) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_scene_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "machine");
  std::ofstream(dir / "machine" / "x.csv") << "x_mm,delta_xx_um\n0,1\n100,nan\n900,2\n";
  std::string text = default_text();
  text = replace(text, "tables: [machine/x_axis.csv,", "tables: [machine/x.csv,");
  const auto scene_file = dir / "s.yaml";
  std::ofstream(scene_file) << text;
  try {
    scene::load_scene(scene_file);
    FAIL() << "accepted a NaN in an error table";
  } catch (const geartopo::InputError& e) {
    EXPECT_EQ(e.file(), (dir / "machine" / "x.csv").string());
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find(":3:"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// Issue 44: the default scene copied to another folder names tables that are not there. The error names the scene
// file, the line and column of the table's entry, the path looked for and that it is relative to the scene file; read
// from text without a file name (Python's scene_from_yaml without source=), that it was the working folder.
TEST(SceneMachine, ATableNotBesideACopiedSceneIsLocatedInTheSceneWithTheResolvedPath) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_scene_copy_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string text = default_text();
  const auto scene_file = dir / "copy.yaml";
  std::ofstream(scene_file) << text;
  // The tables line, and the column of its first entry (1-based).
  const auto at = text.find("tables: [machine/x_axis.csv");
  ASSERT_NE(at, std::string::npos);
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  const int column = static_cast<int>(at - text.rfind('\n', at)) + static_cast<int>(std::string("tables: [").size());
  try {
    scene::load_scene(scene_file);
    ADD_FAILURE() << "a table that does not exist was accepted";
  } catch (const geartopo::InputError& e) {
    EXPECT_EQ(e.file(), scene_file.string());
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(std::string(e.what()),
              fmt::format("{}:{}:{}: machine.tables: table machine/x_axis.csv not found: {} does not exist (a table's "
                          "path is relative to the scene file, in {})",
                          scene_file.string(), line, column, (dir / "machine" / "x_axis.csv").string(), dir.string()));
  }
  std::filesystem::remove_all(dir);
  const auto from_text = error_of_source(text, "");
  EXPECT_NE(from_text.find("machine.tables: table machine/x_axis.csv not found: " +
                           (std::filesystem::current_path() / "machine" / "x_axis.csv").string() +
                           " does not exist (a table's path is relative to the scene file; this scene has no file "
                           "name (read from text), so relative to the working folder)"),
            std::string::npos)
      << from_text;
}

TEST(SceneSections, WheelProcessAndMeasurementAreChecked) {
  const std::string text = default_text();
  EXPECT_NE(error_as_default(replace(text, "outer_diameter_mm: 350", "outer_diameter_mm: 60"))
                .find("wheel.outer_diameter_mm: 60 mm is too small"),
            std::string::npos);
  EXPECT_NE(error_as_default(replace(text, "index_step: 1 ", "index_step: 7 ")).find("process.index_step: 7 does not visit every space"),
            std::string::npos);
  EXPECT_NE(error_as_default(replace(text, "stroke: up", "stroke: sideways")).find("process.stroke: 'sideways' is not one of"),
            std::string::npos);
  EXPECT_NE(error_as_default(replace(text, "helix_points: 150", "helix_points: 150\n  teeth: [1, 36]"))
                .find("measurement.teeth: '36' is not a tooth number of 1..35"),
            std::string::npos);
  EXPECT_NE(error_as_default(replace(text, "helix_points: 150", "helix_points: 150\n  dense_rows: 50"))
                .find("measurement.dense_cols: missing"),
            std::string::npos);
  EXPECT_NE(error_as_default(replace(text, "feed_mm_per_min: 1200", "feed_mm_per_min: 0")).find("process.feed_mm_per_min: 0 is outside [1, 100000]"),
            std::string::npos);
  // Issue 18: a denormal feed passed "> 0" and made every stroke time infinite (crashes in diagnose, inf in time_s).
  EXPECT_NE(error_as_default(replace(text, "feed_mm_per_min: 1200", "feed_mm_per_min: 1e-320")).find("process.feed_mm_per_min: 1e-320 is outside [1, 100000]"),
            std::string::npos);
  // A 10⁸-point grid per flank (10⁹ and more for the gear) is refused before anything is allocated: each of
  // dense_rows, dense_cols has --dense's bound (limits::kMaxGridLines), so the product stays below 4·10⁶ per flank.
  const auto huge = error_as_default(replace(text, "helix_points: 150", "helix_points: 150\n  dense_rows: 10000\n  dense_cols: 10000"));
  EXPECT_NE(huge.find("measurement.dense_rows: 10000 is outside [2, 1000]"), std::string::npos) << huge;
}

TEST(Scene, ThicknessAllowancesAndBallAreReadInTheirUnits) {
  const auto sc = scene::parse_scene(kGood + "  thickness_allowance_upper_um: -80\n  thickness_allowance_lower_um: -160\n"
                                              "  ball_diameter_mm: 24\n",
                                     "mem");
  EXPECT_NEAR(sc.gear.thickness_allowance_upper_mm, -0.080, 1e-15);
  EXPECT_NEAR(sc.gear.thickness_allowance_lower_mm, -0.160, 1e-15);
  ASSERT_TRUE(sc.gear.ball_diameter_mm.has_value());
  EXPECT_DOUBLE_EQ(*sc.gear.ball_diameter_mm, 24.0);
  const auto defaults = scene::parse_scene(kGood, "mem");
  EXPECT_EQ(defaults.gear.thickness_allowance_upper_mm, 0.0);
  EXPECT_EQ(defaults.gear.thickness_allowance_lower_mm, 0.0);
  EXPECT_FALSE(defaults.gear.ball_diameter_mm.has_value());
}

TEST(Scene, LowerAllowanceAboveUpperIsLocated) {
  EXPECT_EQ(error_of(kGood + "  thickness_allowance_upper_um: -100\n  thickness_allowance_lower_um: -50\n"),
            "scenes/x.yaml:11:33: gear.thickness_allowance_lower_um: -50 µm is above thickness_allowance_upper_um = "
            "-100 µm (A_sni ≤ A_sne)");
  const auto ball = error_of(kGood + "  ball_diameter_mm: 0\n");
  EXPECT_EQ(ball, "scenes/x.yaml:10:21: gear.ball_diameter_mm: 0 is outside [0.001, 1000]: below 0.001 mm (1 µm) a dimension is smaller than the µm deviations geartopo computes: no gear, wheel or probe is that small");
}

TEST(Scene, NegativeUpperAllowanceAloneIsBlamedOnTheUpperKey) {
  EXPECT_EQ(error_of(kGood + "  thickness_allowance_upper_um: -40\n"),
            "scenes/x.yaml:10:33: gear.thickness_allowance_upper_um: -40 µm is below the lower allowance 0 µm "
            "(absent: 0; A_sni ≤ A_sne)");
}

// The report's header keys (docs/scene-format.md, `report`): optional free text, a probe diameter in mm and a class.
TEST(SceneReport, HeaderKeysAreReadAndCheckedAtTheirField) {
  const auto sc = scene::parse_scene(kGood + "report:\n  part: P-4711\n  drawing: Z 12-345\n  operator: A. Smith\n"
                                             "  measuring_machine: P 65\n  probe_diameter_mm: 3\n  tolerance_class: 6\n",
                                     "mem");
  EXPECT_EQ(sc.report.part, "P-4711");
  EXPECT_EQ(sc.report.drawing, "Z 12-345");
  EXPECT_EQ(sc.report.operator_name, "A. Smith");
  EXPECT_EQ(sc.report.measuring_machine, "P 65");
  ASSERT_TRUE(sc.report.probe_diameter_mm.has_value());
  EXPECT_DOUBLE_EQ(*sc.report.probe_diameter_mm, 3.0);
  ASSERT_TRUE(sc.report.tolerance_class.has_value());
  EXPECT_EQ(*sc.report.tolerance_class, 6);
  const auto none = scene::parse_scene(kGood, "mem");
  EXPECT_TRUE(none.report.part.empty());
  EXPECT_FALSE(none.report.probe_diameter_mm.has_value());
  EXPECT_FALSE(none.report.tolerance_class.has_value());
  // Lines 10 and 11 of the file: "report:" and the key.
  EXPECT_EQ(error_of(kGood + "report:\n  probe_diameter_mm: 0\n"), "scenes/x.yaml:11:22: report.probe_diameter_mm: 0 is outside [0.001, 100]: below 0.001 mm (1 µm) a dimension is smaller than the µm deviations geartopo computes: no gear, wheel or probe is that small");
  EXPECT_NE(error_of(kGood + "report:\n  tolerance_class: 12\n").find("report.tolerance_class"), std::string::npos);
  EXPECT_NE(error_of(kGood + "report:\n  machine: x\n").find("report.machine"), std::string::npos); // unknown key
}

namespace {

// Two effects with uncertain values and correlations, one across the effects (kGood has 9 lines: `effects:` is line 10).
const std::string kUncertainEffects = kGood + R"(effects:
  - type: thermal_drift
    x_growth_um: 23
    time_constant_s: 94
    uncertainty: {x_growth_um: 4.1, time_constant_s: 48}
    correlation: [[x_growth_um, time_constant_s, 0.8]]
  - type: wheel_wear
    wear_um_per_stroke: 0.05
    uncertainty: {wear_um_per_stroke: 0.01}
    correlation: [[wear_um_per_stroke, thermal_drift.x_growth_um, -0.3]]
)";

} // namespace

// docs/scene-format.md, "Uncertain effects": per-value standard uncertainties in the value's unit and correlation
// entries [key_a, key_b, r] become Scene::effect_uncertainties and the N × N effect_correlation (values in scene order:
// x_growth, z_growth, time_constant, wear, dressing_interval).
TEST(SceneEffects, UncertaintiesAndCorrelationsAreRead) {
  const auto sc = scene::parse_scene(kUncertainEffects, "mem");
  ASSERT_EQ(sc.effect_uncertainties.size(), 2u);
  EXPECT_EQ(sc.effect_uncertainties[0], (std::vector<double>{4.1, 0.0, 48.0}));
  EXPECT_EQ(sc.effect_uncertainties[1], (std::vector<double>{0.01, 0.0}));
  Eigen::MatrixXd expected = Eigen::MatrixXd::Identity(5, 5);
  expected(0, 2) = expected(2, 0) = 0.8;
  expected(3, 0) = expected(0, 3) = -0.3;
  EXPECT_EQ(sc.effect_correlation, expected);
  // Without them the effects are exact and independent, as before.
  const auto plain = scene::parse_scene(kGood + "effects:\n  - {type: thermal_drift, x_growth_um: 9}\n", "mem");
  EXPECT_TRUE(plain.effect_uncertainties.empty());
  EXPECT_EQ(plain.effect_correlation.size(), 0);
}

TEST(SceneEffects, BadUncertaintiesAndCorrelationsAreLocated) {
  // kUncertainEffects with the line that contains `part` replaced by `line`.
  const auto with = [](const std::string& part, const std::string& line) {
    const auto pos = kUncertainEffects.find(part);
    EXPECT_NE(pos, std::string::npos) << part;
    const auto start = kUncertainEffects.rfind('\n', pos) + 1, end = kUncertainEffects.find('\n', pos);
    return kUncertainEffects.substr(0, start) + line + kUncertainEffects.substr(end);
  };
  EXPECT_EQ(error_of(with("uncertainty: {x_growth_um", "    uncertainty: {x_growth_um: -1}")),
            "scenes/x.yaml:14:32: effects[0].uncertainty.x_growth_um: -1 is outside [0, 1000]");
  EXPECT_EQ(error_of(with("uncertainty: {x_growth_um", "    uncertainty: {y_growth_um: 1}")),
            "scenes/x.yaml:14:18: effects[0].uncertainty.y_growth_um: 'y_growth_um' is not a parameter of thermal_drift "
            "(x_growth_um, z_growth_um, time_constant_s)");
  EXPECT_EQ(error_of(with("uncertainty: {wear", "    uncertainty: {dressing_interval_strokes: 1}")),
            "scenes/x.yaml:18:18: effects[1].uncertainty.dressing_interval_strokes: 'dressing_interval_strokes' is a "
            "count set up on the machine, not an uncertain value");
  EXPECT_EQ(error_of(with("correlation: [[x_growth", "    correlation: [[x_growth_um, time_constant_s, 1.2]]")),
            "scenes/x.yaml:15:50: effects[0].correlation[0]: '1.2' is not a correlation coefficient (a number in [-1, 1])");
  EXPECT_EQ(error_of(with("correlation: [[x_growth", "    correlation: [[x_growth_um, 0.8]]")),
            "scenes/x.yaml:15:19: effects[0].correlation[0]: expected [key_a, key_b, r]: two parameter keys and a "
            "correlation coefficient");
  EXPECT_EQ(error_of(with("correlation: [[x_growth", "    correlation: [[x_growth_um, x_growth_um, 0.5]]")),
            "scenes/x.yaml:15:19: effects[0].correlation[0]: 'x_growth_um' with itself: its correlation is 1");
  EXPECT_EQ(error_of(with("correlation: [[wear", "    correlation: [[wear_um_per_stroke, eccentricity.ecc_x_um, 0.1]]")),
            "scenes/x.yaml:19:19: effects[1].correlation[0]: 'eccentricity.ecc_x_um': no effect of type 'eccentricity' "
            "in this scene");
  EXPECT_EQ(error_of(with("correlation: [[wear", "    correlation: [[wear_um_per_stroke, thermal_drift.tau_s, 0.1]]")),
            "scenes/x.yaml:19:19: effects[1].correlation[0]: 'thermal_drift.tau_s' is not a parameter of thermal_drift "
            "(another effect's: type.key)");
  EXPECT_EQ(error_of(with("correlation: [[wear", "    correlation: [[thermal_drift.time_constant_s, thermal_drift.x_growth_um, 0.1]]")),
            "scenes/x.yaml:19:19: effects[1].correlation[0]: the pair thermal_drift.time_constant_s, "
            "thermal_drift.x_growth_um is given twice");
  // Pairwise within [-1, 1] but jointly impossible: a and b, a and c strongly alike, b and c strongly opposite.
  // Eigenvalues of [[1, .9, .9], [.9, 1, -.9], [.9, -.9, 1]]: 1.9, 1.9, -0.8.
  const std::string drift_only = kGood + "effects:\n  - type: thermal_drift\n    correlation: [[x_growth_um, z_growth_um, 0.9], "
                                         "[x_growth_um, time_constant_s, 0.9], [z_growth_um, time_constant_s, -0.9]]\n";
  EXPECT_EQ(error_of(drift_only),
            "scenes/x.yaml:12:19: effects[0].correlation[0]: the effects' correlation coefficients are not a "
            "correlation matrix (not positive semidefinite: smallest eigenvalue -0.8); no joint distribution has them");
}

namespace {

// Two effects drawn from value sets, jointly (kGood has 9 lines: `effects:` is line 10, the drift's second set line 18,
// the wear's `keys` line 23). The drift's sets give two of its three values; z_growth stays at the effect's value in
// every set. A message about the whole `draws` map stands at its first key (column 7).
const std::string kDrawnEffects = kGood + R"(effects:
  - type: thermal_drift
    x_growth_um: 9
    time_constant_s: 540
    draws:
      keys: [x_growth_um, time_constant_s]
      sets:
        - [8, 400]
        - [12, 900]
        - [30, 3000]
  - type: wheel_wear
    wear_um_per_stroke: 0.05
    draws:
      keys: [wear_um_per_stroke]
      sets: [[0.04], [0.05], [0.06]]
)";

} // namespace

// docs/scene-format.md, "Effects drawn from a posterior": sets × every value of the effect (parameter order), the keys
// not listed at the effect's own value; set j of every effect belongs together.
TEST(SceneEffects, ValueSetsAreReadAsWholeValueVectors) {
  const auto sc = scene::parse_scene(kDrawnEffects, "mem");
  ASSERT_EQ(sc.effect_draws.size(), 2u);
  Eigen::MatrixXd drift(3, 3), wear(3, 2);
  drift << 8, 0, 400, 12, 0, 900, 30, 0, 3000; // x_growth, z_growth (the effect's 0), τ
  wear << 0.04, 25, 0.05, 25, 0.06, 25;        // wear, dressing interval (its default, 25 strokes)
  EXPECT_EQ(sc.effect_draws[0], drift);
  EXPECT_EQ(sc.effect_draws[1].col(0), wear.col(0));
  EXPECT_TRUE((sc.effect_draws[1].col(1).array() == sc.effects[1].values[1]).all());
  EXPECT_TRUE(sc.effect_uncertainties.empty());
  EXPECT_EQ(sc.effect_correlation.size(), 0);
  // Without sets: none.
  EXPECT_TRUE(scene::parse_scene(kUncertainEffects, "mem").effect_draws.empty());
}

TEST(SceneEffects, BadValueSetsAreLocated) {
  const auto with = [](const std::string& part, const std::string& line) {
    const auto pos = kDrawnEffects.find(part);
    EXPECT_NE(pos, std::string::npos) << part;
    const auto start = kDrawnEffects.rfind('\n', pos) + 1, end = kDrawnEffects.find('\n', pos);
    return kDrawnEffects.substr(0, start) + line + kDrawnEffects.substr(end);
  };
  EXPECT_EQ(error_of(with("- [12, 900]", "        - [12, 5]")),
            "scenes/x.yaml:18:16: effects[0].draws.sets[1]: time_constant_s 5 is outside its allowed range [10, 1000000]");
  EXPECT_EQ(error_of(with("- [12, 900]", "        - [12]")),
            "scenes/x.yaml:18:11: effects[0].draws.sets[1]: expected [x_growth_um, time_constant_s]: one number per key");
  EXPECT_EQ(error_of(with("- [12, 900]", "        - [12, fast]")),
            "scenes/x.yaml:18:16: effects[0].draws.sets[1]: time_constant_s: 'fast' is not a number");
  EXPECT_EQ(error_of(with("keys: [x_growth_um, time", "      keys: [x_growth_um, tau_s]")),
            "scenes/x.yaml:15:27: effects[0].draws.keys: 'tau_s' is not a parameter of thermal_drift (x_growth_um, "
            "z_growth_um, time_constant_s)");
  EXPECT_EQ(error_of(with("keys: [wear", "      keys: [dressing_interval_strokes]")),
            "scenes/x.yaml:23:14: effects[1].draws.keys: 'dressing_interval_strokes' is a count set up on the machine, "
            "not a drawn value");
  EXPECT_EQ(error_of(with("sets: [[0.04]", "      sets: [[0.04], [0.05]]")),
            "scenes/x.yaml:23:7: effects[1].draws: 2 value sets here, 3 in effects[0].draws: the sets of all effects are "
            "drawn together, set j of each with set j of the others");
  EXPECT_EQ(error_of(with("sets: [[0.04]", "      sets: [[0.04]]")),
            "scenes/x.yaml:24:13: effects[1].draws.sets: expected a list of 2 … 100000 value sets [v, …]");
  EXPECT_EQ(error_of(with("wear_um_per_stroke: 0.05", "    wear_um_per_stroke: 0.05\n    uncertainty: {wear_um_per_stroke: 0.01}")),
            "scenes/x.yaml:24:7: effects[1].draws: wheel_wear has value sets and an uncertainty: give one or the other");
  EXPECT_EQ(error_of(with("wear_um_per_stroke: 0.05", "    wear_um_per_stroke: 0.05\n    correlation: [[wear_um_per_stroke, thermal_drift.x_growth_um, 0.1]]")),
            "scenes/x.yaml:24:7: effects[1].draws: wheel_wear has value sets and an own correlation: give one or the other");
  EXPECT_EQ(error_of(kGood + "effects:\n  - type: wheel_wear\n    uncertainty: {wear_um_per_stroke: 0.01}\n"
                             "    correlation: [[wear_um_per_stroke, thermal_drift.x_growth_um, 0.1]]\n"
                             "  - type: thermal_drift\n    draws: {keys: [x_growth_um], sets: [[1], [2]]}\n"),
            "scenes/x.yaml:13:19: effects[0].correlation[0]: 'thermal_drift.x_growth_um': thermal_drift is drawn from its "
            "value sets (draws), which carry its correlations");
  EXPECT_EQ(error_of(with("keys: [wear", "      key: [wear_um_per_stroke]")),
            "scenes/x.yaml:23:7: effects[1].draws.key: unknown key (known here: keys, sets)");
  EXPECT_EQ(error_of(with("keys: [wear", "      sets_: []")),
            "scenes/x.yaml:23:7: effects[1].draws.sets_: unknown key (known here: keys, sets)");
}

// Standard-uncertainty columns in the scene's tables (docs/error-components.md, "Uncertainty columns"): the example
// table of docs/examples read through a scene, a components override of the same component refused at its key, a bad
// column reported in the table file.
namespace {
const std::string kExampleTable = "../docs/examples/x_axis_with_uncertainty.csv"; // relative to scenes/

std::string default_with_example_x_table() {
  return replace(default_text(), "machine/x_axis.csv", kExampleTable);
}

int line_of(const std::string& text, const std::string& what) {
  const auto pos = text.find(what);
  EXPECT_NE(pos, std::string::npos) << what;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
}
} // namespace

TEST(SceneMachine, TheExampleTableBringsItsUncertaintyColumns) {
  const auto sc = scene::parse_scene(default_with_example_x_table(), kDefault);
  const auto& sources = sc.machine.sources;
  const auto source = [&](machine::ComponentId id) -> const machine::ErrorSource& {
    const auto it = std::find_if(sources.begin(), sources.end(), [&](const auto& s) { return s.id() == id; });
    EXPECT_NE(it, sources.end());
    return *it;
  };
  EXPECT_TRUE(source(machine::ComponentId::delta_xx).has_uncertainty_column());
  EXPECT_TRUE(source(machine::ComponentId::epsilon_zx).has_uncertainty_column());
  EXPECT_FALSE(source(machine::ComponentId::delta_yx).has_uncertainty_column());
  // u_delta_xx_um at 300 mm is 0.8 µm in the file.
  EXPECT_NEAR(source(machine::ComponentId::delta_xx).uncertainty(300.0), 0.8e-3, 1e-12);
  // The scene still builds (strokes covered) and an override of a component without a column is fine.
  EXPECT_EQ(error_as_default(replace(default_with_example_x_table(), "  constants:",
                                     "  uncertainty: {components: {delta_yx_um: 0.7}}\n  constants:")),
            "(no error)");
}

TEST(SceneMachine, AnOverrideOfAComponentWithAnUncertaintyColumnIsRefused) {
  const std::string text = replace(default_with_example_x_table(), "  constants:",
                                   "  uncertainty: {linear_axis_um: 2, components: {delta_xx_um: 0.7}}\n  constants:");
  const std::string what = error_as_default(text);
  const std::string where = kDefault + ":" + std::to_string(line_of(text, "components: {delta_xx_um")) + ":";
  EXPECT_EQ(what.rfind(where, 0), 0u) << what;
  EXPECT_NE(what.find("machine.uncertainty.components.delta_xx_um: delta_xx's standard uncertainty is already given "
                      "by table"),
            std::string::npos)
      << what;
  EXPECT_NE(what.find("x_axis_with_uncertainty.csv column 3 'u_delta_xx_um'"), std::string::npos) << what;
}

TEST(SceneMachine, ABadUncertaintyColumnIsLocatedInTheTableFile) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_scene_u_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "machine");
  std::ofstream(dir / "machine" / "x.csv") << "x_mm,delta_xx_um,u_delta_xx_um\n0,1,0.5\n450,1.5,-0.5\n900,2,0.5\n";
  const auto scene_file = dir / "s.yaml";
  std::ofstream(scene_file) << replace(default_text(), "tables: [machine/x_axis.csv,", "tables: [machine/x.csv,");
  try {
    scene::load_scene(scene_file);
    ADD_FAILURE() << "accepted a negative standard uncertainty";
  } catch (const geartopo::InputError& e) {
    EXPECT_EQ(e.file(), (dir / "machine" / "x.csv").string());
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find(":3:9: u_delta_xx_um: '-0.5' is negative"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// gear.modifications and process.lead_crowning (issue 26): values read per flank over `both`, and every bad value
// located at its key with the allowed range — nan, inf, negative amounts, huge values, unknown shapes, a relief that
// starts outside the active profile (both numbers named), an end relief of half the face width or more.
TEST(Scene, ModificationsAreReadPerFlankAndBadValuesLocated) {
  const std::string mods = kGood + "  modifications:\n"
                                   "    both: {profile_crowning_um: 4, helix_crowning_um: 6, tip_relief_um: 8, tip_relief_start_diameter_mm: 592}\n"
                                   "    right: {helix_crowning_um: 3, end_relief_shape: arc}\n"
                                   "process: {lead_crowning: radial_infeed}\n";
  const auto sc = scene::parse_scene(mods, "mem");
  EXPECT_EQ(sc.gear.modifications.left.helix_crowning_um, 6.0);
  EXPECT_EQ(sc.gear.modifications.right.helix_crowning_um, 3.0);
  EXPECT_EQ(sc.gear.modifications.right.profile_crowning_um, 4.0); // from both
  EXPECT_EQ(sc.gear.modifications.right.tip_relief_start_diameter_mm, 592.0);
  EXPECT_EQ(sc.gear.modifications.right.end_relief_shape, gears::ReliefShape::Arc);
  EXPECT_EQ(sc.process.lead_crowning, grinding::LeadCrowning::RadialInfeed);
  EXPECT_EQ(scene::parse_scene(kGood, "mem").process.lead_crowning, grinding::LeadCrowning::TwistFree);

  const auto with_both = [](const std::string& both) { return kGood + "  modifications:\n    both: {" + both + "}\n"; };
  EXPECT_EQ(error_of(with_both("profile_crowning_um: .nan")),
            "scenes/x.yaml:11:33: gear.modifications.both.profile_crowning_um: '.nan' is not a number");
  EXPECT_EQ(error_of(with_both("helix_crowning_um: .inf")),
            "scenes/x.yaml:11:31: gear.modifications.both.helix_crowning_um: '.inf' is not a number");
  EXPECT_EQ(error_of(with_both("tip_relief_um: -2")),
            "scenes/x.yaml:11:27: gear.modifications.both.tip_relief_um: -2 is outside [0, 1000]");
  EXPECT_EQ(error_of(with_both("helix_slope_um: 1e9")),
            "scenes/x.yaml:11:28: gear.modifications.both.helix_slope_um: 1e9 is outside [-1000, 1000]");
  EXPECT_NE(error_of(with_both("tip_relief_shape: round")).find("gear.modifications.both.tip_relief_shape: 'round' is not one of: linear, arc"),
            std::string::npos);
  EXPECT_NE(error_of(with_both("crowning_um: 3")).find("gear.modifications.both.crowning_um: unknown key"), std::string::npos);
  const std::string outside = error_of(with_both("tip_relief_um: 8, tip_relief_start_diameter_mm: 610"));
  EXPECT_EQ(outside.rfind("scenes/x.yaml:11:60: gear.modifications.both.tip_relief_start_diameter_mm: 610 mm is outside the "
                          "active profile",
                          0),
            0u)
      << outside;
  EXPECT_NE(outside.find("d_a = 601.475 mm"), std::string::npos) << outside;
  const std::string end = error_of(kGood + "  modifications:\n    left: {end_relief_um: 5, end_relief_length_mm: 75}\n");
  EXPECT_EQ(end.rfind("scenes/x.yaml:11:52: gear.modifications.left.end_relief_length_mm: 75 mm is outside the face width", 0),
            0u)
      << end;
  EXPECT_NE(error_of(kGood + "process: {lead_crowning: hobbed}\n").find("process.lead_crowning: 'hobbed' is not one of: twist_free, radial_infeed"),
            std::string::npos);
}

// gear.modifications.table (issue 26): a CSV beside the scene, read into per-flank grids; every bad line located at
// file:line:column and field; an incomplete grid named by its missing point; a grid short of L_α × L_β refused at
// gear.modifications.table with both ranges.
TEST(Scene, ADesignTableIsReadAndItsFaultsLocated) {
  const auto dir = std::filesystem::temp_directory_path() / ("geartopo_scene_dt_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto scene_with = [&](const std::string& csv) {
    std::ofstream(dir / "design.csv") << csv;
    std::ofstream(dir / "scene.yaml") << kGood << "  modifications: {table: design.csv}\n";
    try {
      return std::make_pair(scene::load_scene(dir / "scene.yaml"), std::string());
    } catch (const InputError& e) {
      return std::make_pair(scene::Scene{}, std::string(e.what()));
    }
  };
  std::string good = "# a crowned right flank, flat left\nflank,diameter_mm,z_mm,design_um\n";
  for (const char* f : {"left", "right"})
    for (double d : {540.0, 605.0})
      for (double z : {0.0, 75.0, 150.0})
        good += std::string(f) + "," + std::to_string(d) + "," + std::to_string(z) + "," +
                (std::string(f) == "right" && z == 75.0 ? "0" : (std::string(f) == "right" ? "-6" : "0")) + "\n";
  const auto [sc, err] = scene_with(good);
  ASSERT_TRUE(err.empty()) << err;
  const auto& right = sc.gear.modifications.table.right;
  EXPECT_EQ(right.diameter_mm, (std::vector<double>{540.0, 605.0}));
  EXPECT_EQ(right.z_mm, (std::vector<double>{0.0, 75.0, 150.0}));
  EXPECT_EQ(right.value_um, (std::vector<double>{-6, 0, -6, -6, 0, -6}));
  const std::string file = (dir / "design.csv").string();
  const std::string head = "flank,diameter_mm,z_mm,design_um\n";
  EXPECT_EQ(scene_with(head + "right,540,0,nan\n").second, file + ":2:13: design_um: 'nan' is not finite");
  EXPECT_EQ(scene_with(head + "middle,540,0,1\n").second, file + ":2:1: flank: 'middle' is neither left nor right");
  EXPECT_EQ(scene_with(head + "right,540,0\n").second, file + ":2:12: row: 3 fields, expected 4");
  EXPECT_EQ(scene_with(head + "right,540,0,2e6\n").second,
            file + ":2:13: design_um: 2e6 µm is beyond ±1000 µm, more than a drawing modifies a flank (a wrong unit?)");
  EXPECT_EQ(scene_with("flank,d_mm,z_mm,design_um\n").second, file + ":1:1: header: expected the columns " + head.substr(0, head.size() - 1));
  EXPECT_EQ(scene_with(head + "right,540,0,1\nright,540,0,2\n").second,
            file + ":3:1: row: duplicate point: right flank, d = 540 mm, z = 0 mm");
  EXPECT_EQ(scene_with(head + "right,540,0,1\nright,605,0,1\nright,540,150,1\n").second,
            file + ": rows: the right flank's grid has no point at d = 605 mm, z = 150 mm: every diameter needs every z");
  const std::string short_of_l_beta = scene_with(head + "right,540,20,1\nright,605,20,1\nright,540,150,1\nright,605,150,1\n").second;
  EXPECT_NE(short_of_l_beta.find("gear.modifications.table: the right flank of " + file + " covers z 20.000 … 150.000 mm"),
            std::string::npos)
      << short_of_l_beta;
  std::filesystem::remove_all(dir);
}

TEST(SceneMachineChanges, EveryLawIsReadInItsFileUnits) {
  const auto sc = scene::parse_scene(kGood + R"(machine_changes:
  - {component: E_AOA, law: linear_in_time, rate_urad_per_min: 40}
  - {component: delta_yy, law: steady_state, final_um: 6, time_constant_s: 900}
  - {component: epsilon_zc, law: once_per_revolution, amplitude_urad: 25, phase_deg: 90}
  - {component: E_XOC, change_um: 3}
)", "mem");
  ASSERT_EQ(sc.machine_changes.size(), 4u);
  const auto& c = sc.machine_changes;
  EXPECT_EQ(c[0].component, machine::ComponentId::E_AOA);
  EXPECT_EQ(c[0].law, machine::ChangeLaw::LinearInTime);
  EXPECT_NEAR(c[0].size, 40e-6 / 60.0, 1e-18);                 // rad per second
  EXPECT_NEAR(c[0].at(120.0, 0.0), 80e-6, 1e-15);               // two minutes in
  EXPECT_NEAR(c[1].at(900.0, 0.0), 6e-3 * (1.0 - std::exp(-1.0)), 1e-15); // mm, one time constant in
  EXPECT_NEAR(c[2].at(0.0, std::numbers::pi / 2), 25e-6, 1e-15); // largest at C = φ = 90°
  EXPECT_NEAR(c[2].at(0.0, 0.0), 0.0, 1e-15);
  EXPECT_EQ(c[3].law, machine::ChangeLaw::Constant);           // the default law
  EXPECT_NEAR(c[3].at(1e4, 1.0), 3e-3, 1e-15);
  EXPECT_EQ(sc.machine_change_uncertainties, (std::vector<double>{0.0, 0.0, 0.0, 0.0}));
  const auto u = scene::parse_scene(kGood + "machine_changes:\n  - {component: E_AOA, law: linear_in_time, "
                                            "rate_urad_per_min: 40, uncertainty: {rate_urad_per_min: 1.2}}\n", "mem");
  EXPECT_EQ(u.machine_change_uncertainties, std::vector<double>{1.2});
}

TEST(SceneMachineChanges, PeriodicLawsOfAnyOrderAreRead) {
  const auto sc = scene::parse_scene(kGood + R"(machine_changes:
  - {component: epsilon_zc, law: twice_per_revolution, amplitude_urad: 10, phase_deg: 60}
  - {component: delta_xc, law: 5_times_per_revolution, amplitude_um: 2, phase_deg: 0}
  - {component: epsilon_zc, law: once_per_revolution, amplitude_urad: 3, phase_deg: 0}
)", "mem");
  ASSERT_EQ(sc.machine_changes.size(), 3u);
  const auto& c = sc.machine_changes;
  EXPECT_EQ(c[0].law, machine::ChangeLaw::PerRevolution);
  EXPECT_EQ(c[0].order, 2);
  // a cos(2γ − φ): largest where 2γ = 60°, at γ = 30° and 210°; zero at 2γ − φ = 90°, γ = 75°.
  EXPECT_NEAR(c[0].at(0.0, std::numbers::pi / 6), 10e-6, 1e-15);
  EXPECT_NEAR(c[0].at(0.0, 7 * std::numbers::pi / 6), 10e-6, 1e-15);
  EXPECT_NEAR(c[0].at(0.0, 75.0 * std::numbers::pi / 180.0), 0.0, 1e-15);
  EXPECT_EQ(c[1].order, 5);
  EXPECT_NEAR(c[1].at(0.0, 2 * std::numbers::pi / 5), 2e-3, 1e-15); // one period of five on
  EXPECT_EQ(c[1].law_name(), "5_times_per_revolution");
  EXPECT_EQ(c[2].order, 1); // the same component with another order is another change
  const auto err = [](const std::string& item) { return error_of(kGood + "machine_changes:\n  - " + item + "\n"); };
  for (const char* law : {"0_times_per_revolution", "1_times_per_revolution", "2_times_per_revolution",
                          "03_times_per_revolution", "1001_times_per_revolution", "x_times_per_revolution",
                          "per_revolution"})
    EXPECT_NE(err(fmt::format("{{component: epsilon_zc, law: {}, amplitude_urad: 5, phase_deg: 0}}", law))
                  .find("scenes/x.yaml:11:34: machine_changes[0].law: '"),
              std::string::npos)
        << law;
  EXPECT_NE(err("{component: E_AOA, law: 3_times_per_revolution, amplitude_urad: 5, phase_deg: 0}")
                .find("3_times_per_revolution needs a C-axis motion component"),
            std::string::npos);
}

TEST(SceneMachineChanges, BadChangesAreLocated) {
  const auto err = [](const std::string& item) { return error_of(kGood + "machine_changes:\n  - " + item + "\n"); };
  EXPECT_EQ(err("{component: E_ABC, change_um: 3}"),
            "scenes/x.yaml:11:17: machine_changes[0].component: 'E_ABC' is not an error component (docs/error-components.md)");
  EXPECT_EQ(err("{component: E_AOA, change_um: 3}"),
            "scenes/x.yaml:11:35: machine_changes[0].change_um: E_AOA is an angle (urad): give change_urad");
  EXPECT_NE(err("{component: E_AOA, change_urad: .nan}").find("machine_changes[0].change_urad"), std::string::npos);
  EXPECT_NE(err("{component: E_AOA, change_urad: 1e9}").find("is outside [-10000, 10000]"), std::string::npos);
  EXPECT_NE(err("{component: E_AOA, law: sometimes, change_urad: 1}").find("machine_changes[0].law"), std::string::npos);
  EXPECT_NE(err("{component: delta_yy, law: steady_state, final_um: 6}").find("time_constant_s"), std::string::npos);
  EXPECT_NE(err("{component: E_AOA, law: once_per_revolution, amplitude_urad: 5, phase_deg: 0}")
                .find("once_per_revolution needs a C-axis motion component"),
            std::string::npos);
  const std::string twice = error_of(kGood + "machine_changes:\n  - {component: E_XOC, change_um: 3}\n"
                                             "  - {component: E_XOC, change_um: 4}\n");
  EXPECT_EQ(twice, "scenes/x.yaml:12:17: machine_changes[1].component: E_XOC with law constant is listed twice");
  EXPECT_NE(error_of(kGood + "machine_changes: {component: E_XOC}\n").find("expected a list"), std::string::npos);
  EXPECT_NE(err("{component: E_XOC, change_um: 3, uncertainty: {change_um: -1}}").find("is outside [0, 1000]"),
            std::string::npos);
  EXPECT_NE(err("{component: E_XOC, change_um: 3, uncertainty: {change_urad: 1}}").find("uncertainty"), std::string::npos);
}

// measurement.measured_against (issue 39): what the scene's measurement is measured from when it has no design_um
// column — design or involute, and only beside measured (alone it would say nothing).
TEST(Scene, MeasuredAgainstTakesDesignOrInvoluteBesideMeasured) {
  const auto sc = scene::parse_scene(kGood + "measurement:\n  measured: m.csv\n  measured_against: design\n", "mem");
  EXPECT_EQ(sc.grid.measured_against, "design");
  EXPECT_TRUE(scene::parse_scene(kGood + "measurement:\n  measured: m.csv\n", "mem").grid.measured_against.empty());
  EXPECT_EQ(error_of(kGood + "measurement:\n  measured: m.csv\n  measured_against: drawing\n"),
            "scenes/x.yaml:12:21: measurement.measured_against: 'drawing' is not one of: design, involute");
  EXPECT_NE(error_of(kGood + "measurement:\n  measured_against: design\n")
                .find("measurement.measured_against: says nothing without measured"),
            std::string::npos);
}
