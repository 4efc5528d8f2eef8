// The value-file reader (.mew, docs/measurement-formats.md "Value file") on a hand-written file written from the
// documented structure ([V] gearcore p40/gina parser), not by geartopo: codes decoded and cross-checked against their
// labels, placeholders, settings, unknown lines kept, and a located error for every line it cannot read.
#include "geartopo/core/input_error.hpp"
#include "geartopo/measurement/klingelnberg_values.hpp"

#include "example_text.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace geartopo;
using measurement::MachineQuantity;
using measurement::MachineStatistic;

namespace values_test {

const std::string kExample = std::string(GEARTOPO_SOURCE_DIR) + "/tests/measurement/data/klingelnberg_example.mew";

std::string example_text() { return test::file_text(kExample); }

using test::replaced;

std::string error_of(const std::string& text) {
  try {
    (void)measurement::parse_klingelnberg_values(text, "x.mew");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

} // namespace values_test


TEST(KlingelnbergValues, ReadsTheExampleByCodeAndLabel) {
  const auto f = measurement::read_klingelnberg_values(values_test::kExample);
  // Per tooth and flank, the first position (MM 01/04/07), by the label's tooth number.
  ASSERT_NE(f.find(MachineQuantity::HelixSlope, 1, Flank::Left), nullptr);
  EXPECT_DOUBLE_EQ(*f.find(MachineQuantity::HelixSlope, 1, Flank::Left)->value_um, -3.2);
  EXPECT_EQ(f.find(MachineQuantity::HelixSlope, 1, Flank::Left)->line, 21);
  EXPECT_DOUBLE_EQ(*f.find(MachineQuantity::HelixSlope, 1, Flank::Right)->value_um, 2.1);
  EXPECT_DOUBLE_EQ(*f.find(MachineQuantity::HelixSlope, 12, Flank::Left)->value_um, -2.8);
  EXPECT_EQ(f.find(MachineQuantity::HelixSlope, 12, Flank::Left)->slot, 2);
  EXPECT_DOUBLE_EQ(*f.find(MachineQuantity::HelixTotal, 1, Flank::Left)->value_um, 4.0);
  EXPECT_DOUBLE_EQ(*f.find(MachineQuantity::HelixForm, 1, Flank::Left)->value_um, 1.1);
  EXPECT_DOUBLE_EQ(*f.find(MachineQuantity::ProfileSlope, 1, Flank::Left)->value_um, 5.5);
  EXPECT_DOUBLE_EQ(*f.find(MachineQuantity::ProfileTotal, 1, Flank::Right)->value_um, 6.25);
  EXPECT_DOUBLE_EQ(*f.find(MachineQuantity::ProfileForm, 1, Flank::Right)->value_um, 1.75);
  EXPECT_EQ(f.find(MachineQuantity::ProfileForm, 1, Flank::Left), nullptr); // not in the file
  // Placeholders are kept as "no value", never as numbers.
  ASSERT_NE(f.find(MachineQuantity::ProfileSlope, 12, Flank::Left), nullptr);
  EXPECT_FALSE(f.find(MachineQuantity::ProfileSlope, 12, Flank::Left)->value_um);
  EXPECT_FALSE(f.find(MachineQuantity::ProfileSlope, 12, Flank::Right)->value_um);
  EXPECT_EQ(f.placeholders, 2);
  // Second positions, statistics and f_Ko are read but are not the per-tooth values.
  int second = 0, statistics = 0, tip_relief = 0;
  for (const auto& v : f.flank_values) {
    second += v.position != 0;
    statistics += v.statistic != MachineStatistic::Tooth;
    tip_relief += v.measurand == 16;
    if (v.code == 20211) { EXPECT_EQ(v.position, 'u'); }
    if (v.code == 10311) { EXPECT_EQ(v.position, 'k'); }
    if (v.code == 10430) { EXPECT_EQ(v.statistic, MachineStatistic::Mean); }
    if (v.code == 10150) { EXPECT_EQ(v.statistic, MachineStatistic::Variation); }
    if (v.code == 20760) { EXPECT_EQ(v.flank, Flank::Right); }
    if (v.code == 20190) { EXPECT_EQ(v.statistic, MachineStatistic::Min); }
  }
  EXPECT_EQ(second, 2);
  EXPECT_EQ(statistics, 7);
  EXPECT_EQ(tip_relief, 1);
  EXPECT_EQ(f.flank_values.size(), 20u);
  // Settings and filters as text; 179 BZGFL 1: f_Hβ referred to b.
  ASSERT_EQ(f.settings.size(), 4u);
  EXPECT_EQ(f.settings.at(178).text, "Vorzeichen Flankenlinie...........: LVORZ: 1: DIN");
  EXPECT_EQ(f.settings.at(180).number, 0);
  EXPECT_TRUE(f.helix_slope_referred_to_face_width());
  ASSERT_EQ(f.filters.size(), 2u);
  EXPECT_EQ(f.filters[1], "FILTER LEAD:    F:S 2");
  // Pitch and runout by label; sizes kept as unknown lines.
  ASSERT_EQ(f.pitch_values.size(), 4u);
  EXPECT_EQ(f.pitch_values[0].name, "fp max");
  EXPECT_EQ(f.pitch_values[0].flank, Flank::Left);
  EXPECT_EQ(f.pitch_values[2].name, "Fr");
  EXPECT_FALSE(f.pitch_values[2].flank);
  EXPECT_EQ(f.pitch_values[3].name, "Fpz/8");
  ASSERT_EQ(f.unknown_lines.size(), 1u);
  EXPECT_EQ(f.unknown_lines[0], "50001 Fuß (line 45)");
}

// Latin-1 without BOM, LF, and decimal commas throughout read to the same values.
TEST(KlingelnbergValues, Latin1LfAndDecimalCommasReadTheSame) {
  std::string text = values_test::example_text().substr(3); // no BOM
  std::string lf;
  for (const char c : text)
    if (c != '\r') lf += c;
  const auto a = measurement::parse_klingelnberg_values(values_test::example_text(), "a.mew");
  // latin-1: ä and ß as one byte each
  std::string latin1 = values_test::replaced(values_test::replaced(lf, "Zähnezahl", "Z\xE4hnezahl"), "Fuß", "Fu\xDF");
  const auto b = measurement::parse_klingelnberg_values(latin1, "b.mew");
  ASSERT_EQ(a.flank_values.size(), b.flank_values.size());
  for (std::size_t i = 0; i < a.flank_values.size(); ++i) EXPECT_EQ(a.flank_values[i].value_um, b.flank_values[i].value_um);
  EXPECT_EQ(b.unknown_lines[0], "50001 Fuß (line 45)");
  // Decimal commas in every result value.
  std::string comma;
  std::istringstream in(lf);
  for (std::string line; std::getline(in, line);) {
    if (line.size() > 5 && std::isdigit(static_cast<unsigned char>(line[0])) && line[5] == ' ')
      if (const auto dot = line.rfind('.'); dot != std::string::npos && dot > line.rfind(':')) line[dot] = ',';
    comma += line + "\n";
  }
  const auto c = measurement::parse_klingelnberg_values(comma, "c.mew");
  ASSERT_EQ(a.flank_values.size(), c.flank_values.size());
  for (std::size_t i = 0; i < a.flank_values.size(); ++i) EXPECT_EQ(a.flank_values[i].value_um, c.flank_values[i].value_um);
  // One separator per file: a point after commas is refused at its place.
  const auto e = values_test::error_of(values_test::replaced(comma, "10711 : ffb links 1 : 1,1", "10711 : ffb links 1 : 1.1"));
  EXPECT_NE(e.find("x.mew:25:"), std::string::npos) << e;
  EXPECT_NE(e.find("decimal point, but this file's numbers have a decimal comma"), std::string::npos) << e;
}

// A label that does not say what its code says is an error at its line: a changed export is not misread.
TEST(KlingelnbergValues, ALabelThatContradictsItsCodeIsAnError) {
  const std::string t = values_test::example_text();
  const std::pair<std::string, std::string> cases[] = {
      {"10411 : Fb links 1 : 4.0", "10411 : ffb links 1 : 4.0"},        // another quantity
      {"10121 : fHb rechts 1 : 2.1", "10121 : fHb links 1 : 2.1"},      // another flank
      {"10130 : fHbm links : -3.0", "10130 : fHb links 1 : -3.0"},      // per tooth, code says mean
      {"20211 : fHa links u 1u : 5.0", "20211 : fHa links 1 : 5.0"},    // no second position
      {"20211 : fHa links u 1u : 5.0", "20211 : fHa links f 1f : 5.0"}, // a helix position on a profile value
      {"20170 : fHa links max : 5.5", "20170 : fHa links min : 5.5"},   // max, label says min
      {"10111 : fHb links 1 : -3.2", "10111 : fHb links : -3.2"},       // no tooth
      {"10111 : fHb links 1 : -3.2", "10111 : fHb Links 1 : -3.2"},     // a word not understood
  };
  for (const auto& [from, to] : cases) {
    const auto e = values_test::error_of(values_test::replaced(t, from, to));
    EXPECT_NE(e.find("x.mew:"), std::string::npos) << to << " → " << e;
    EXPECT_NE(e.find("code and label disagree"), std::string::npos) << to << " → " << e;
  }
  const auto e = values_test::error_of(values_test::replaced(t, "10411 : Fb links 1 : 4.0", "10411 : ffb links 1 : 4.0"));
  EXPECT_NE(e.find("x.mew:24:"), std::string::npos) << e;
  EXPECT_NE(e.find("names 'ffb' (expected 'Fb')"), std::string::npos) << e;
}

TEST(KlingelnbergValues, RepeatedCodesSlotsAndUnreadableLinesAreLocatedErrors) {
  const std::string t = values_test::example_text();
  auto e = values_test::error_of(values_test::replaced(t, "10711 : ffb links 1 : 1.1", "10411 : Fb links 1 : 4.1"));
  EXPECT_NE(e.find("x.mew:25:1: 10411: code 10411 is given twice (first at line 24)"), std::string::npos) << e;
  // Slot 2 is tooth 12: tooth 13 in slot 2, or tooth 1 in slot 2, is refused.
  e = values_test::error_of(values_test::replaced(t, "10112 : fHb links 12 : -2.8", "10112 : fHb links 13 : -2.8"));
  EXPECT_NE(e.find("slot 2 is tooth 12 here and tooth 13"), std::string::npos) << e;
  e = values_test::error_of(values_test::replaced(t, "20112 : fHa links 12 : -9999.0", "20112 : fHa links 1 : -9999.0"));
  EXPECT_NE(e.find("x.mew:27:1: 20112: slot 2 is tooth 1 here and tooth 12 at line 23"), std::string::npos) << e;
  e = values_test::error_of(values_test::replaced(t, "21611 : fKo links 1 : 12.0", "21613 : fKo links 12 : 12.0"));
  EXPECT_NE(e.find("tooth 12 is in slot 3 here and in slot 2"), std::string::npos) << e;
  // A statistic with a slot, a per-tooth value without one.
  e = values_test::error_of(values_test::replaced(t, "10130 : fHbm links : -3.0", "10131 : fHbm links : -3.0"));
  EXPECT_NE(e.find("statistics have 0"), std::string::npos) << e;
  e = values_test::error_of(values_test::replaced(t, "21611 : fKo links 1 : 12.0", "21610 : fKo links 1 : 12.0"));
  EXPECT_NE(e.find("slots are 1 … 5"), std::string::npos) << e;
  // Values that are not numbers or beyond ±1000 µm; a line without a label.
  e = values_test::error_of(values_test::replaced(t, "10121 : fHb rechts 1 : 2.1", "10121 : fHb rechts 1 : nan"));
  EXPECT_NE(e.find("x.mew:22:24: 10121: 'nan' is not a number"), std::string::npos) << e;
  e = values_test::error_of(values_test::replaced(t, "10121 : fHb rechts 1 : 2.1", "10121 : fHb rechts 1 : 2100"));
  EXPECT_NE(e.find("beyond ±1000 µm"), std::string::npos) << e;
  e = values_test::error_of(values_test::replaced(t, "10121 : fHb rechts 1 : 2.1", "10121 : fHb rechts 1 : 2.1 2.2"));
  EXPECT_NE(e.find("expected one value"), std::string::npos) << e;
  e = values_test::error_of(values_test::replaced(t, "10121 : fHb rechts 1 : 2.1", "10121 : 2.1"));
  EXPECT_NE(e.find("expected '<code> : <label> : <value>'"), std::string::npos) << e;
  // Not a value file; a line of no known kind.
  e = values_test::error_of(values_test::replaced(t, "HEADER KS.MW.FILE", "HEADER KS.MK.FILE"));
  EXPECT_NE(e.find("x.mew:1:1: HEADER: this is a curve file"), std::string::npos) << e;
  e = values_test::error_of(values_test::replaced(t, "10121 : fHb rechts 1 : 2.1", "Profil:  Zahn-Nr.: 1 links / 5 Werte / z= 10.0"));
  EXPECT_NE(e.find("x.mew:22:"), std::string::npos) << e;
  EXPECT_NE(e.find("is neither a setting"), std::string::npos) << e;
  EXPECT_NE(values_test::error_of("").find("the file is empty"), std::string::npos);
}
