// Value ± uncertainty as a reader sees it, GUM (JCGM 100:2008) §7.2.6: u to two significant digits, the value to the
// same decimal place. Truth: the GUM's own example (y = 10.057 62 Ω, u_c = 27 mΩ → 10.058 Ω) and the rule applied by
// hand to the values the diagnosis console printed before (issue 15).
#include "geartopo/core/uncertain_value.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using geartopo::text::with_uncertainty;

TEST(UncertainValue, RoundsTheUncertaintyToTwoDigitsAndTheValueToTheSamePlace) {
  EXPECT_EQ(with_uncertainty(10.05762, 0.027), "10.058 ± 0.027"); // GUM §7.2.6's example
  EXPECT_EQ(with_uncertainty(-0.2223, 110.3), "0 ± 110");          // was "-0.2223 ± 1.1e+02"
  EXPECT_EQ(with_uncertainty(10.5, 490.2), "10 ± 490");
  EXPECT_EQ(with_uncertainty(813.0, 8.04e4), "1000 ± 80000"); // 813 to the thousands
  EXPECT_EQ(with_uncertainty(0.05696, 0.00384), "0.0570 ± 0.0038");
  EXPECT_EQ(with_uncertainty(-1.371, 0.7312), "-1.37 ± 0.73");
  EXPECT_EQ(with_uncertainty(24.36, 5.41), "24.4 ± 5.4");
  EXPECT_EQ(with_uncertainty(106.7, 59.2), "107 ± 59");
  EXPECT_EQ(with_uncertainty(1234.4, 10.47), "1234 ± 10"); // to nearest (GUM allows rounding u up: not done)
}

TEST(UncertainValue, ACarryIntoANewDigitKeepsTwoSignificantDigits) {
  EXPECT_EQ(with_uncertainty(1.23456, 0.0997), "1.23 ± 0.10");
  EXPECT_EQ(with_uncertainty(512.0, 99.7), "510 ± 100");
  EXPECT_EQ(with_uncertainty(0.5, 0.001), "0.5000 ± 0.0010");
}

TEST(UncertainValue, SignsAndValuesWithoutAUsableUncertainty) {
  EXPECT_EQ(with_uncertainty(2.0012, 0.061, true), "+2.001 ± 0.061");
  EXPECT_EQ(with_uncertainty(-0.004, 0.13, true), "+0.00 ± 0.13"); // rounds to zero: no "-0.00"
  EXPECT_EQ(with_uncertainty(-0.1, 0.13, true), "-0.10 ± 0.13");
  EXPECT_EQ(with_uncertainty(3.14159, 0.0), "3.142 ± 0");
  EXPECT_EQ(with_uncertainty(3.14159, std::nan("")), "3.142 ± nan");
  EXPECT_EQ(with_uncertainty(3.14159, INFINITY), "3.142 ± inf");
}

} // namespace
