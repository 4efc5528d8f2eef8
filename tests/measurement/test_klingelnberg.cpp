// The Klingelnberg export reader (docs/measurement-formats.md) on a hand-written file whose values follow known
// patterns, its error messages, and the round trip through the writer `synth --format klingelnberg` uses.
#include "geartopo/core/input_error.hpp"
#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/diagnosis/synth.hpp"
#include "geartopo/gears/gear_geometry.hpp"
#include "geartopo/workbench/workbench.hpp"

#include "example_text.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

using namespace geartopo;

namespace {

const std::string kExample = std::string(GEARTOPO_SOURCE_DIR) + "/tests/measurement/data/klingelnberg_example.mka";
constexpr double kDeg = std::numbers::pi / 180.0;

// The gear the example file describes: m_n = 2, z = 24, α_n = 20°, β = 15°, x = 0, b = 20, conventional d_a, d_f.
gears::GearGeometry example_gear(double mn = 2.0, int z = 24) {
  gears::GearSpec s;
  s.normal_module_mm = mn;
  s.teeth = z;
  s.normal_pressure_angle_rad = 20.0 * kDeg;
  s.helix_angle_rad = 15.0 * kDeg;
  s.face_width_mm = 20.0;
  s.tip_diameter_mm = gears::conventional_tip_diameter(s);
  s.root_diameter_mm = gears::conventional_root_diameter(s);
  return gears::GearGeometry(s);
}

std::string example_text() { return test::file_text(kExample); }

using test::replaced;

std::string points_error(const std::string& text, const gears::GearGeometry& g) {
  try {
    (void)measurement::klingelnberg_points(measurement::parse_klingelnberg(text, "x.mka"), g);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// cos β_b for β = 15°, α_n = 20°, written out: sin β_b = sin β cos α_n.
const double kCosBetaB = std::cos(std::asin(std::sin(15.0 * kDeg) * std::cos(20.0 * kDeg)));

} // namespace

TEST(Klingelnberg, ExampleFileGivesTheKnownPattern) {
  const auto g = example_gear();
  const auto file = measurement::read_klingelnberg(kExample);
  EXPECT_EQ(file.traces.size(), 5u);
  EXPECT_EQ(file.undefined_points, 1);
  EXPECT_TRUE(file.skipped_blocks.empty());
  ASSERT_EQ(file.pitch.size(), 4u);
  EXPECT_EQ(file.pitch[1].tooth, 2);
  EXPECT_EQ(file.pitch[1].flank, Flank::Left);
  EXPECT_DOUBLE_EQ(file.pitch[1].fp_um, -0.4);
  EXPECT_DOUBLE_EQ(file.pitch[1].Fp_um, 0.262);
  EXPECT_DOUBLE_EQ(file.pitch[1].Fr_um, 1.1);
  EXPECT_EQ(file.pitch[2].flank, Flank::Right);
  EXPECT_EQ(file.codes.at(22).label, "Zähnezahl z");
  // Line 27 says "da" too, but only measuring/evaluation lines define the range: da is line 41's 47.5.
  EXPECT_DOUBLE_EQ(file.ranges.at("da").values.at(0), 47.5);

  const auto res = measurement::klingelnberg_points(file, g);
  ASSERT_EQ(res.points.size(), 20u); // 5 + 5 + 3 (one undefined) + 4 + 3
  ASSERT_EQ(res.warnings.size(), 1u);
  EXPECT_EQ(res.warnings[0], kExample + ": 1 undefined values (-2147483.648) skipped");

  const double rb = 0.5 * g.base_diameter_mm();
  auto xi = [&](double d) { return std::sqrt(0.25 * d * d - rb * rb); };
  // Profile, tooth 1 left: raw 0 1 2 3 4 µm, evenly in roll length over da 47.5 … de 53.2 at z = 10; the raw sign of a
  // left profile is the opposite of DIN's, and transverse values are × cos β_b along the normal.
  for (int i = 0; i < 5; ++i) {
    const auto& p = res.points[static_cast<size_t>(i)];
    EXPECT_EQ(p.tooth, 1);
    EXPECT_EQ(p.flank, Flank::Left);
    EXPECT_NEAR(p.roll_length_mm, xi(47.5) + i / 4.0 * (xi(53.2) - xi(47.5)), 1e-9);
    EXPECT_NEAR(p.z_mm, 10.0, 1e-12);
    EXPECT_NEAR(p.deviation_um, -1.0 * i * kCosBetaB, 1e-9);
    EXPECT_EQ(p.line, 23);
  }
  // Profile, tooth 1 right: raw = DIN, slope −0.5 µm per step.
  for (int i = 0; i < 5; ++i) {
    const auto& p = res.points[static_cast<size_t>(5 + i)];
    EXPECT_EQ(p.flank, Flank::Right);
    EXPECT_NEAR(p.deviation_um, -0.5 * i * kCosBetaB, 1e-9);
  }
  EXPECT_NEAR(res.points[5].diameter_mm, 47.5, 1e-9);
  EXPECT_NEAR(res.points[9].diameter_mm, 53.2, 1e-9);
  // Helix, tooth 1 right at d = 50: 4 values evenly over ba 2 … be 18, the first undefined; helix raw × −1 = DIN.
  for (int i = 1; i < 4; ++i) {
    const auto& p = res.points[static_cast<size_t>(9 + i)];
    EXPECT_EQ(p.tooth, 1);
    EXPECT_NEAR(p.diameter_mm, 50.0, 1e-9);
    EXPECT_NEAR(p.z_mm, 2.0 + i * 16.0 / 3.0, 1e-9);
    EXPECT_NEAR(p.deviation_um, (i + 1.0) * kCosBetaB, 1e-9);
  }
  EXPECT_EQ(res.points[10].line, 27); // the value after the undefined one
  EXPECT_EQ(res.points[12].line, 28); // on the next line
  // Helix, tooth 2 left, title on its own line and the position as roll length x = 10 mm.
  for (int i = 0; i < 4; ++i) {
    const auto& p = res.points[static_cast<size_t>(13 + i)];
    EXPECT_EQ(p.tooth, 2);
    EXPECT_EQ(p.flank, Flank::Left);
    EXPECT_NEAR(p.roll_length_mm, 10.0, 1e-9);
    EXPECT_NEAR(p.deviation_um, (i + 1.0) * kCosBetaB, 1e-9);
  }
  // Topography line of tooth 2 right at z = 5: a constant +0.046 µm.
  for (int i = 0; i < 3; ++i) {
    const auto& p = res.points[static_cast<size_t>(17 + i)];
    EXPECT_EQ(p.flank, Flank::Right);
    EXPECT_NEAR(p.z_mm, 5.0, 1e-12);
    EXPECT_NEAR(p.roll_length_mm, xi(47.5) + i / 2.0 * (xi(53.2) - xi(47.5)), 1e-9);
    EXPECT_NEAR(p.deviation_um, 0.046 * kCosBetaB, 1e-12);
  }
}

TEST(Klingelnberg, OptionsChangeSpacingDirectionAndSign) {
  const auto g = example_gear();
  measurement::KlingelnbergOptions o;
  o.spacing = measurement::ProfileSpacing::Diameter;
  o.direction = measurement::DeviationDirection::Normal;
  o.signs = measurement::SignConvention::Din;
  const auto res = measurement::klingelnberg_points(measurement::read_klingelnberg(kExample), g, o);
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(res.points[static_cast<size_t>(i)].diameter_mm, 47.5 + i / 4.0 * 5.7, 1e-9);
    EXPECT_NEAR(res.points[static_cast<size_t>(i)].deviation_um, 1.0 * i, 1e-12);
  }
}

TEST(Klingelnberg, Latin1AndLfReadTheSame) {
  std::string text = example_text().substr(3); // without the BOM
  std::string latin1;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\r') continue;
    if (static_cast<unsigned char>(text[i]) == 0xC3) { // ä ß: two UTF-8 bytes → one latin-1 byte
      latin1 += static_cast<char>(static_cast<unsigned char>(text[i + 1]) + 0x40);
      ++i;
    } else {
      latin1 += text[i];
    }
  }
  const auto g = example_gear();
  const auto a = measurement::klingelnberg_points(measurement::parse_klingelnberg(latin1, "l.mka"), g);
  const auto b = measurement::klingelnberg_points(measurement::read_klingelnberg(kExample), g);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(a.points[i].deviation_um, b.points[i].deviation_um);
  EXPECT_EQ(measurement::parse_klingelnberg(latin1, "l.mka").codes.at(22).label, "Zähnezahl z");
}

TEST(Klingelnberg, HeaderMustMatchTheScene) {
  EXPECT_EQ(points_error(example_text(), example_gear(2.5)),
            "x.mka:6: 21 Normalmodul mn [mm]: 2 mm in the file, the scene's gear has m_n = 2.5 mm");
  EXPECT_EQ(points_error(example_text(), example_gear(2.0, 25)),
            "x.mka:7: 22 Zähnezahl z: 24 in the file, the scene's gear has z = 25");
}

TEST(Klingelnberg, UnknownBlocksAreListedNotUsed) {
  const std::string text = example_text() +
                           "Verschränkung: Zahn-Nr.: 1k /Flankenlinie:3 links / 2  Werte  x= 10.263\r\n  1.0  2.0\r\n"
                           "Teilung:\r\nZ-Nr. Seite PHI X Y Z\r\n  1   R  0.0000  .1198  25.5249  87.2302\r\n";
  const auto res = measurement::klingelnberg_points(measurement::parse_klingelnberg(text, "x.mka"), example_gear());
  EXPECT_EQ(res.points.size(), 20u);
  ASSERT_EQ(res.warnings.size(), 2u);
  EXPECT_EQ(res.warnings[0], "x.mka: blocks not read (this reader knows Profil, Flankenlinie, TOPOGRAFIE and the pitch "
                             "tables): Verschränkung (line 42), Teilung (line 44)");
}

// fuzz_klingelnberg (2026-11-27): a line of separators only (";") has no tokens, and the reader took its first token
// (undefined behaviour: UBSan's "reference binding to null pointer", a crash in Release). It reads as a blank line.
TEST(Klingelnberg, ALineOfSeparatorsOnlyIsABlankLine) {
  const auto ref = measurement::klingelnberg_points(measurement::parse_klingelnberg(example_text(), "x.mka"), example_gear());
  std::string text = example_text(); // a ";" line after its first (the export's header line, BOM first)
  text.insert(text.find('\n') + 1, ";\r\n");
  const auto res = measurement::klingelnberg_points(measurement::parse_klingelnberg(text, "x.mka"), example_gear());
  ASSERT_EQ(res.points.size(), ref.points.size());
  for (size_t i = 0; i < ref.points.size(); ++i) EXPECT_EQ(res.points[i].deviation_um, ref.points[i].deviation_um);
  EXPECT_EQ(res.warnings, ref.warnings);
}

// The fifth fuzzing run: a ";" line in the pitch table (after its last row, or before its column line) read the first
// token of none (UBSan). It is a blank line there too: the same points, warnings and pitch rows.
TEST(Klingelnberg, ALineOfSeparatorsOnlyIsABlankLineInThePitchTable) {
  const auto ref_file = measurement::parse_klingelnberg(example_text(), "x.mka");
  std::string text = example_text();
  text.insert(text.find("Zahn-Nr.   fp"), ";\r\n");                                   // before the left table's head
  text.insert(text.find("\n", text.find("  2      -.400")) + 1, " ; ;\r\n");           // after its last row
  text += ";";                                                                     // the file's last line
  const auto file = measurement::parse_klingelnberg(text, "x.mka");
  ASSERT_EQ(file.pitch.size(), ref_file.pitch.size());
  for (size_t i = 0; i < file.pitch.size(); ++i) {
    EXPECT_EQ(file.pitch[i].tooth, ref_file.pitch[i].tooth);
    EXPECT_EQ(file.pitch[i].flank, ref_file.pitch[i].flank);
    EXPECT_EQ(file.pitch[i].fp_um, ref_file.pitch[i].fp_um);
    EXPECT_EQ(file.pitch[i].Fp_um, ref_file.pitch[i].Fp_um);
    EXPECT_EQ(file.pitch[i].Fr_um, ref_file.pitch[i].Fr_um);
  }
  const auto ref = measurement::klingelnberg_points(ref_file, example_gear());
  const auto res = measurement::klingelnberg_points(file, example_gear());
  ASSERT_EQ(res.points.size(), ref.points.size());
  for (size_t i = 0; i < ref.points.size(); ++i) EXPECT_EQ(res.points[i].deviation_um, ref.points[i].deviation_um);
  EXPECT_EQ(res.warnings, ref.warnings);
}

TEST(Klingelnberg, CountsMustMatchTheHead) {
  const auto few = replaced(example_text(), "  .000  1.000  2.000  3.000  4.000", "  .000  1.000  2.000  3.000");
  EXPECT_EQ(points_error(few, example_gear()), "x.mka:22: Werte: the head announces 5 values, 4 follow");
  const auto many = replaced(example_text(), "  .000  1.000  2.000  3.000  4.000", "  .000  1.000  2.000  3.000  4.000 5");
  EXPECT_EQ(points_error(many, example_gear()), "x.mka:23: Werte: more values than the 5 announced by the head at line 22");
  const auto word = replaced(example_text(), "/ 5 Werte / z= 10.0", "/ fünf Werte / z= 10.0");
  EXPECT_EQ(points_error(word, example_gear()), "x.mka:22: Werte: 'fünf' is not a number of values");
}

// Issue 30: "nan" among the values was reported as "the head announces 5 values, 0 follow"; it is a value that is
// not a number, said at its line and column. An absurd value (a wrong unit) is refused at its place too.
TEST(Klingelnberg, AValueThatIsNotANumberIsNamedAtItsPlace) {
  const std::string values = "  .000  1.000  2.000  3.000  4.000";
  const auto nan = replaced(example_text(), values, "  .000  1.000  nan  3.000  4.000");
  EXPECT_EQ(points_error(nan, example_gear()),
            "x.mka:23:16: Werte: 'nan' is not a number: value 3 of the profile trace of tooth 1 (head at line 22); numbers "
            "are written 1.5, -.046 or 1e-3 (1,5 and -,046 throughout a file with decimal commas); a point the machine "
            "could not measure is written -2147483.648");
  EXPECT_NE(points_error(replaced(example_text(), values, "  inf  1.000  2.000  3.000  4.000"), example_gear())
                .find("x.mka:23:3: Werte: 'inf' is not a number: value 1 of"),
            std::string::npos);
  EXPECT_NE(points_error(replaced(example_text(), values, "  .000  1.000  2.000  3.000  1e300"), example_gear())
                .find("x.mka:23:30: Werte: 1e300 µm is beyond ±1000 µm"),
            std::string::npos);
  // The undefined value itself stays a skipped point (the example has one).
  EXPECT_EQ(measurement::read_klingelnberg(kExample).undefined_points, 1);
}

// Issue 30, repeated traces: a second block of the same tooth, flank, kind and position (another tooth's blocks
// numbered wrongly, or a repeat) is refused; the same tooth at another position is another trace.
TEST(Klingelnberg, ATraceMeasuredTwiceIsRefused) {
  const std::string text = example_text();
  const auto lines = std::count(text.begin(), text.end(), '\n');
  const std::string again = "Profil:  Zahn-Nr.: 1 links / 5 Werte / z= 10.0\r\n  .100  1.200  2.100  3.300  4.200\r\n";
  EXPECT_EQ(points_error(text + again, example_gear()).rfind(
                fmt::format("x.mka:{}: Zahn-Nr.: tooth 1 left profile at z= 10 mm is measured twice (first at line 22): "
                            "a repeated measurement is refused",
                            lines + 1),
                0),
            0u)
      << points_error(text + again, example_gear());
  const std::string elsewhere = "Profil:  Zahn-Nr.: 1 links / 5 Werte / z= 12.0\r\n  .100  1.200  2.100  3.300  4.200\r\n";
  EXPECT_EQ(measurement::parse_klingelnberg(text + elsewhere, "x.mka").traces.size(), 6u);
}

TEST(Klingelnberg, NothingUsableIsAnError) {
  const std::string header_only = example_text().substr(0, example_text().find("Profil:"));
  EXPECT_EQ(points_error(header_only, example_gear()),
            "x.mka:21: Zahn-Nr.: nothing usable: 0 profile/helix traces, no defined point on the active flank");
  // A trace entirely off the flank (z beyond the face width) is not usable either.
  const std::string off = header_only + "Profil:  Zahn-Nr.: 1 links / 2 Werte / z= 25.0\r\n 1.0 2.0\r\n";
  EXPECT_EQ(points_error(off, example_gear()),
            "x.mka:23: Zahn-Nr.: nothing usable: 1 profile/helix traces, no defined point on the active flank");
}

TEST(Klingelnberg, IsRecognisedByItsContent) {
  std::ifstream in(kExample, std::ios::binary);
  EXPECT_TRUE(measurement::looks_like_klingelnberg(in));
  std::istringstream csv("tooth,flank,row,col,diameter_mm,z_mm,deviation_um\n");
  EXPECT_FALSE(measurement::looks_like_klingelnberg(csv));
}

// Writer and reader are inverse to the printed precision: positions 1e-6 mm, deviations 0.001 µm (× 1/cos β_b in the
// file, × cos β_b back).
TEST(Klingelnberg, SynthesizedTopographyRoundTrips) {
  const workbench::Workbench wb(std::string(GEARTOPO_SOURCE_DIR) + "/scenes/truth-skmc1200w-mn14-z35.yaml");
  diagnosis::SynthOptions so;
  so.teeth = {1, 18};
  const auto rows = diagnosis::synthesize(wb.setup, wb.process(), so);
  std::ostringstream out;
  measurement::write_klingelnberg(out, wb.setup.geometry(), rows);
  const auto res = measurement::klingelnberg_points(measurement::parse_klingelnberg(out.str(), "synth.mka"), wb.setup.geometry());
  ASSERT_EQ(res.points.size(), rows.size());
  EXPECT_TRUE(res.warnings.empty());
  for (const auto& r : rows) {
    const auto it = std::find_if(res.points.begin(), res.points.end(), [&](const measurement::MeasuredPoint& p) {
      return p.tooth == r.tooth && p.flank == r.flank && std::abs(p.z_mm - r.z_mm) < 1e-5 &&
             std::abs(p.diameter_mm - r.diameter_mm) < 1e-5;
    });
    ASSERT_NE(it, res.points.end()) << "tooth " << r.tooth << " row " << r.row << " col " << r.col;
    EXPECT_NEAR(it->deviation_um, r.deviation_um, 0.5e-3);
  }
}

TEST(Klingelnberg, DifferentAnglesAreAWarning) {
  const auto text = replaced(example_text(), "beta [Grad]......: 15.0000", "beta [Grad]......: -20.0000");
  const auto res = measurement::klingelnberg_points(measurement::parse_klingelnberg(text, "x.mka"), example_gear());
  ASSERT_EQ(res.warnings.size(), 2u);
  EXPECT_EQ(res.warnings[0], "x.mka:8: 23 Schrägungswinkel beta [Grad]: -20° in the file, 15° in the scene (|β| and α_n "
                             "are compared)");
  // The example's own angles agree: only the undefined point is reported (ExampleFileGivesTheKnownPattern).
}

// Issue 28 item 7: the field's variations. A German export with decimal commas, ';' between the fields, latin-1 and
// CRLF (tests/measurement/data/klingelnberg_decimal_comma.mka, written by hand as the example with ',' for '.') reads
// to the example's values: the first profile's raw 0 1 2 3 4 µm, the pitch table's −0.4 / 0.262 / 1.1 µm.
TEST(KlingelnbergVariations, DecimalCommaFileReadsAsTheExample) {
  const auto comma = measurement::read_klingelnberg(std::string(GEARTOPO_SOURCE_DIR) +
                                                    "/tests/measurement/data/klingelnberg_decimal_comma.mka");
  EXPECT_EQ(comma.codes.at(22).label, "Zähnezahl z");
  EXPECT_DOUBLE_EQ(comma.codes.at(21).values.at(0), 2.0);
  EXPECT_DOUBLE_EQ(comma.ranges.at("de").values.at(1), 53.2);
  ASSERT_EQ(comma.traces.size(), 5u);
  EXPECT_EQ(comma.traces[0].values_um, (std::vector<double>{0.0, 1.0, 2.0, 3.0, 4.0}));
  EXPECT_DOUBLE_EQ(comma.traces[1].values_um[1], -0.5);
  EXPECT_DOUBLE_EQ(comma.traces[3].position_mm, 10.0);
  EXPECT_EQ(comma.undefined_points, 1);
  ASSERT_EQ(comma.pitch.size(), 4u);
  EXPECT_DOUBLE_EQ(comma.pitch[1].fp_um, -0.4);
  EXPECT_DOUBLE_EQ(comma.pitch[1].Fp_um, 0.262);
  EXPECT_DOUBLE_EQ(comma.pitch[1].Fr_um, 1.1);
  const auto g = example_gear();
  const auto a = measurement::klingelnberg_points(comma, g);
  const auto b = measurement::klingelnberg_points(measurement::read_klingelnberg(kExample), g);
  ASSERT_EQ(a.points.size(), 20u);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].deviation_um, b.points[i].deviation_um);
    EXPECT_EQ(a.points[i].z_mm, b.points[i].z_mm);
    EXPECT_EQ(a.points[i].line, b.points[i].line);
  }
}

// One decimal separator per file: a decimal comma among decimal points (or the reverse) is refused at its place,
// naming the number that decided the file's separator.
TEST(KlingelnbergVariations, MixedDecimalSeparatorsAreRefusedAtTheirPlace) {
  const auto mixed = replaced(example_text(), "  .000  1.000  2.000  3.000  4.000", "  .000  1.000  2,838  3.000  4.000");
  EXPECT_EQ(points_error(mixed, example_gear()),
            "x.mka:23:16: Werte: '2,838' has a decimal comma, but this file's numbers have a decimal point (the first, "
            "'2.0000', at line 6): one decimal separator for the whole file: value 3 of the profile trace of tooth 1 "
            "(head at line 22); numbers are written 1.5, -.046 or 1e-3 (1,5 and -,046 throughout a file with decimal "
            "commas); a point the machine could not measure is written -2147483.648");
  std::ifstream in(std::string(GEARTOPO_SOURCE_DIR) + "/tests/measurement/data/klingelnberg_decimal_comma.mka", std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  const auto point = replaced(s.str(), "-1,000; -2,000; -3,000; -4,000", "-1,000; -2.000; -3,000; -4,000");
  EXPECT_NE(points_error(point, example_gear()).find("x.mka:31:11: Werte: '-2.000' has a decimal point, but this file's "
                                                     "numbers have a decimal comma (the first, '2,0000', at line 6)"),
            std::string::npos)
      << points_error(point, example_gear());
}

// A value that is not a number in any file ("--", "2,838" where commas are not decimal, "inf") is named with its line,
// column and what is allowed, not reported as a trace with too few values.
TEST(KlingelnbergVariations, ABadNumberIsNamedWithWhatIsAllowed) {
  const auto dashes = replaced(example_text(), "  .000  1.000  2.000  3.000  4.000", "  --  --  --  --  --");
  EXPECT_NE(points_error(dashes, example_gear())
                .find("x.mka:23:3: Werte: '--' is not a number: value 1 of the profile trace of tooth 1 (head at line 22); "
                      "numbers are written 1.5"),
            std::string::npos)
      << points_error(dashes, example_gear());
}

// Lines without the preamble (no "HEADER KS.MK.FILE", "TYPE", …) read the same; trace blocks without the numbered
// header lines have no measuring range: an error at the first trace naming what is missing.
TEST(KlingelnbergVariations, WithoutPreambleOrHeader) {
  const std::string text = example_text();
  const auto no_preamble = text.substr(text.find("   2 :Datum"));
  const auto res = measurement::klingelnberg_points(measurement::parse_klingelnberg(no_preamble, "x.mka"), example_gear());
  EXPECT_EQ(res.points.size(), 20u);
  EXPECT_NEAR(res.points[1].deviation_um, -1.0 * kCosBetaB, 1e-12);
  const auto no_header = text.substr(text.find("Profil:"));
  const auto file = measurement::parse_klingelnberg(no_header, "x.mka");
  EXPECT_EQ(file.traces.size(), 5u);
  EXPECT_EQ(points_error(no_header, example_gear()),
            "x.mka:1: da: a profile trace needs the measuring range 'da' in the header, which is missing");
}

// Issue 31: the reader is as strict as the writers. Each case is refused at its line, naming what is allowed.
TEST(KlingelnbergStrict, RangesMustRunForwards) {
  const auto reversed = replaced(example_text(), "de [mm].....: 53.2000     53.2000", "de [mm].....: 53.2000     47.0000");
  EXPECT_EQ(points_error(reversed, example_gear()),
            "x.mka:17: de Ende der Messstrecke de [mm]: the range da … de = 47.5 … 47 mm (right flank) is reversed: it "
            "must run forwards (da < de; da at line 14)");
  const auto empty = replaced(example_text(), "be [mm].....: 18.0000     18.0000", "be [mm].....: 2.0000");
  EXPECT_NE(points_error(empty, example_gear()).find("x.mka:21: be Messende be [mm]: the range ba … be = 2 … 2 mm (left flank) is empty"),
            std::string::npos)
      << points_error(empty, example_gear());
}

TEST(KlingelnbergStrict, ModuleAndTeethMustBeReadable) {
  EXPECT_EQ(points_error(replaced(example_text(), "z.......................: 24", "z.......................: vierundzwanzig"),
                         example_gear()),
            "x.mka:7:43: 22 Zähnezahl z: 'vierundzwanzig' is not a number; this line's values are numbers (numbers are "
            "written 1.5, -.046 or 1e-3 (1,5 and -,046 throughout a file with decimal commas))");
  EXPECT_NE(points_error(replaced(example_text(), "z.......................: 24", "z.......................: 24.5"), example_gear())
                .find("x.mka:7: 22 Zähnezahl z: 24.5 is not a number of teeth"),
            std::string::npos);
  EXPECT_NE(points_error(replaced(example_text(), "mn [mm]...............: 2.0000", "mn [mm]...............: nan"), example_gear())
                .find("x.mka:6:43: 21 Normalmodul mn [mm]: 'nan' is not a number"),
            std::string::npos);
  EXPECT_NE(points_error(replaced(example_text(), "mn [mm]...............: 2.0000", "mn [mm]...............:"), example_gear())
                .find("x.mka:6: 21 Normalmodul mn [mm]: no value after the label"),
            std::string::npos);
}

TEST(KlingelnbergStrict, ToothNumbersAreOneToZ) {
  EXPECT_EQ(points_error(replaced(example_text(), "Zahn-Nr.: 1 links", "Zahn-Nr.: 25 links"), example_gear()),
            "x.mka:22: Zahn-Nr.: tooth 25 of a gear with 24 teeth: a whole number 1 … 24 (z, header line 22)");
  EXPECT_EQ(points_error(replaced(example_text(), "Zahn-Nr.: 1 links", "Zahn-Nr.: 1e9 links"), example_gear()),
            "x.mka:22: Zahn-Nr.: '1e9' is not a tooth number: a whole number 1 … 24 (z, header line 22)");
  EXPECT_EQ(points_error(replaced(example_text(), "Zahn-Nr.: 1 links", "Zahn-Nr.: 1000000000 links"), example_gear()),
            "x.mka:22: Zahn-Nr.: tooth 1000000000 of a gear with 24 teeth: a whole number 1 … 24 (z, header line 22)");
}

TEST(KlingelnbergStrict, PitchTableValuesAreNumbersOfRealTeeth) {
  EXPECT_EQ(points_error(replaced(example_text(), "  2      -.400   .262  1.100", "  2      nan   .262  1.100"), example_gear()),
            "x.mka:37:10: fp: 'nan' is not a number: the pitch table's fp of tooth 2 (left flank), in µm; numbers are "
            "written 1.5, -.046 or 1e-3 (1,5 and -,046 throughout a file with decimal commas)");
  EXPECT_NE(points_error(replaced(example_text(), "  2      -.400   .262  1.100", "  2      -.400   .262  1e300"), example_gear())
                .find("x.mka:37:24: Fr: 1e300 µm is beyond ±1000 µm"),
            std::string::npos);
  EXPECT_EQ(points_error(replaced(example_text(), "  2      -.400   .262  1.100", "  1      -.400   .262  1.100"), example_gear()),
            "x.mka:37: Zahn-Nr.: tooth 1 is in the left pitch table twice (first at line 36)");
  EXPECT_EQ(points_error(replaced(example_text(), "  2      -.400   .262  1.100", "  36      -.400   .262  1.100"), example_gear()),
            "x.mka:37:3: Zahn-Nr.: tooth 36 in the pitch table: a tooth number is 1 … 24 (z, header line 22)");
}

// A numbered header line right after a pitch table ends the table and is read as a header line, not as a pitch row
// of tooth 23 with the wrong number of fields. (Code 23 itself, the helix angle, given again with another value is
// refused: KlingelnbergStrict.AHeaderValueGivenTwiceIsRefused.)
TEST(KlingelnbergStrict, AHeaderLineAfterAPitchTableEndsIt) {
  const std::string text = replaced(example_text(), "  2     -.300   .000   .900", "  2     -.300   .000   .900\r\n 23 :Schrägungswinkel beta [Grad]......: 15.0000");
  const auto f = measurement::parse_klingelnberg(text, "x.mka");
  EXPECT_EQ(f.pitch.size(), 4u);
  EXPECT_TRUE(f.codes.count(23)) << "line 23 read as a header";
}

// A header line the reader uses or compares (module, teeth, angles, width, ranges) given again with another value:
// which one the machine meant is not known, so neither is taken (the later one was, silently).
TEST(KlingelnbergStrict, AHeaderValueGivenTwiceIsRefused) {
  const std::string text = replaced(example_text(), "  2     -.300   .000   .900", "  2     -.300   .000   .900\r\n 23 :Datum.............: 1");
  EXPECT_THROW(
      {
        try {
          (void)measurement::parse_klingelnberg(text, "x.mka");
        } catch (const InputError& e) {
          EXPECT_EQ(std::string(e.what()), "x.mka:42: 23 Datum: given again with other values (first at line 8)");
          throw;
        }
      },
      InputError);
}

// A UTF-16 export (Windows "Unicode") is named as such, with what to do, by the export reader and the measurement
// front end alike (not reported as a topology CSV with a bad header).
TEST(KlingelnbergStrict, Utf16IsNamed) {
  const std::string text = example_text().substr(3);
  std::string le = "\xFF\xFE", be = "\xFE\xFF", bare;
  for (const char c : text) {
    le += c;
    le += '\0';
    be += '\0';
    be += c;
    bare += c;
    bare += '\0';
  }
  EXPECT_NE(points_error(le, example_gear()).find("x.mka: the file is UTF-16 (little-endian, byte-order mark FF FE), which "
                                                  "geartopo does not read: save it as UTF-8 or latin-1"),
            std::string::npos);
  EXPECT_NE(points_error(be, example_gear()).find("byte-order mark FE FF"), std::string::npos);
  EXPECT_NE(points_error(bare, example_gear()).find("x.mka: the file is UTF-16 without a byte-order mark"), std::string::npos);
}

// English labels (Profile, Lead, TOPOGRAPHY, Tooth-No., left/right, Values, "left flank", measuring/evaluation range
// lines): tests/measurement/data/klingelnberg_english.mka, the example in English words, UTF-8 without BOM, LF.
TEST(KlingelnbergVariations, EnglishLabelsReadAsTheExample) {
  const auto en = measurement::read_klingelnberg(std::string(GEARTOPO_SOURCE_DIR) + "/tests/measurement/data/klingelnberg_english.mka");
  ASSERT_EQ(en.traces.size(), 5u);
  EXPECT_EQ(en.traces[0].kind, measurement::TraceKind::Profile);
  EXPECT_EQ(en.traces[0].flank, Flank::Left);
  EXPECT_EQ(en.traces[2].kind, measurement::TraceKind::Helix);
  EXPECT_EQ(en.traces[3].position_symbol, 'x');
  EXPECT_TRUE(en.traces[4].topography);
  EXPECT_DOUBLE_EQ(en.ranges.at("da").values.at(0), 47.5); // "measuring range", not line 27's "Tip diameter da"
  EXPECT_DOUBLE_EQ(en.ranges.at("be").values.at(1), 18.0);
  ASSERT_EQ(en.pitch.size(), 4u);
  EXPECT_EQ(en.pitch[2].flank, Flank::Right);
  EXPECT_DOUBLE_EQ(en.pitch[3].fp_um, -0.3);
  EXPECT_TRUE(en.skipped_blocks.empty());
  const auto g = example_gear();
  const auto a = measurement::klingelnberg_points(en, g);
  const auto b = measurement::klingelnberg_points(measurement::read_klingelnberg(kExample), g);
  ASSERT_EQ(a.points.size(), 20u);
  for (size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].deviation_um, b.points[i].deviation_um);
    EXPECT_EQ(a.points[i].roll_length_mm, b.points[i].roll_length_mm);
  }
  // A bad value in an English head is located in the file's own columns.
  std::ifstream in(std::string(GEARTOPO_SOURCE_DIR) + "/tests/measurement/data/klingelnberg_english.mka");
  std::stringstream s;
  s << in.rdbuf();
  const auto bad = points_error(replaced(s.str(), "Tooth-No.: 1 left / 5 Values / z= 10.0", "Tooth-No.: 1 left / 5 Values / z= 1,0"), g);
  EXPECT_EQ(bad.rfind("x.mka:22:45: z=: '1,0' has a decimal comma", 0), 0u) << bad;
}
