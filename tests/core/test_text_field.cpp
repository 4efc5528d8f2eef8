// The number and quoting rule shared by every reader (core/text_field.hpp); that the readers follow it is in
// tests/robustness/test_known_findings.cpp.
#include "geartopo/core/text_field.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace geartopo;

namespace {

bool number(std::string_view s) {
  double v = 0.0;
  return text::parse_number(s, v) == std::errc();
}

} // namespace

TEST(TextField, OneLeadingPlusBeforeADigitOrPointOnly) {
  for (const char* ok : {"5", "+5", "-5", "+.5", "+0.5e3", "1e-300", "-0"}) EXPECT_TRUE(number(ok)) << ok;
  for (const char* bad : {"", "+", "+-5", "++5", "-+5", "+ 5", "5 ", "5,0", "0x10", "+inf", "1e", "."})
    EXPECT_FALSE(number(bad)) << bad;
  double v = 0.0;
  EXPECT_EQ(text::parse_number("1e999", v), std::errc::result_out_of_range);
  int i = 0;
  EXPECT_EQ(text::parse_number("+42", i), std::errc());
  EXPECT_EQ(i, 42);
  EXPECT_NE(text::parse_number("4.2", i), std::errc());
}

TEST(TextField, ExcerptCutsLongFieldsAtACharacterBoundary) {
  EXPECT_EQ(text::excerpt("12.5"), "12.5");
  const std::string micro = std::string(39, '1') + "µm" + std::string(100, '2'); // 'µ' is bytes 40 and 41
  const std::string e = text::excerpt(micro);
  EXPECT_EQ(e, std::string(39, '1') + "… (" + std::to_string(micro.size()) + " characters)");
  std::string_view s = "\xEF\xBB\xBFx_mm";
  EXPECT_TRUE(text::strip_bom(s));
  EXPECT_EQ(s, "x_mm");
  EXPECT_FALSE(text::strip_bom(s));
}
