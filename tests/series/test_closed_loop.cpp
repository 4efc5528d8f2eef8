// The closed loop over a series (closed_loop.hpp), on truths written here from the laws' own formulas.
// Units: µm, h, strokes.
#include "geartopo/series/closed_loop.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <stdexcept>

using namespace geartopo;

namespace {

std::vector<series::GearState> every_half_hour(int gears) {
  std::vector<series::GearState> s;
  for (int k = 0; k < gears; ++k) s.push_back({0.25 + 0.5 * k, 0.0, 0});
  return s;
}

double rms_closed(const std::vector<series::ClosedLoopGear>& g, size_t from) {
  double s = 0.0;
  for (size_t k = from; k < g.size(); ++k) s += g[k].closed_um * g[k].closed_um;
  return std::sqrt(s / static_cast<double>(g.size() - from));
}

} // namespace

// A constant offset of 5 µm and no scatter: gear 1 is ground uncorrected (5 µm), and from gear 2 on the correction is
// −5 µm (the mean of what was seen, then the noise-only law's constant), so every later gear comes out at 0.
TEST(ClosedLoop, ConstantOffsetIsCancelledFromTheSecondGear) {
  series::ClosedLoopInput in;
  in.states = every_half_hour(8);
  in.truth_um = [](const series::GearState&) { return 5.0; };
  const auto loop = series::run_closed_loop(in);
  ASSERT_EQ(loop.size(), 8u);
  EXPECT_DOUBLE_EQ(loop[0].correction_um, 0.0);
  EXPECT_DOUBLE_EQ(loop[0].closed_um, 5.0);
  for (size_t k = 1; k < loop.size(); ++k) {
    EXPECT_DOUBLE_EQ(loop[k].open_um, 5.0) << k;
    EXPECT_NEAR(loop[k].correction_um, -5.0, 1e-9) << k;
    EXPECT_NEAR(loop[k].closed_um, 0.0, 1e-9) << k;
  }
  EXPECT_EQ(loop[7].model, "noise only");
}

// A machine warming from cold: y = 12 (1 − e^(−t/1 h)) µm, a gear every half hour for 8 h, 0.3 µm scatter. Without
// corrections the gears after the first 3 h sit at 11.4 … 12 µm. While the loop has seen too little of the curve for
// the F-test to keep the thermal law it predicts the mean so far and lags the warming; once it names the law (at the
// latest with 6 gears seen) the error left is the prediction's: the gear's own scatter plus the fitted curve's,
// √(1 + p/n) · 0.3 µm ≈ 0.33 µm for p = 3 parameters at n ≥ 6. Over gears 7 … 16 the RMS must stay below twice the
// gear's own scatter, against > 10 µm open.
TEST(ClosedLoop, ThermalDriftErrorFallsToTheScatter) {
  series::ClosedLoopInput in;
  in.states = every_half_hour(16);
  in.truth_um = [](const series::GearState& s) { return 12.0 * (1.0 - std::exp(-s.time_h / 1.0)); };
  in.scatter_um = 0.3;
  in.floor_um = 0.05;
  in.seed = 7;
  const auto loop = series::run_closed_loop(in);
  double open_late = 0.0;
  for (size_t k = 6; k < loop.size(); ++k) {
    open_late += loop[k].open_um * loop[k].open_um / 10.0;
    EXPECT_EQ(loop[k].model, "thermal drift") << "gear " << k + 1;
  }
  EXPECT_GT(std::sqrt(open_late), 10.0);
  EXPECT_LT(rms_closed(loop, 6), 2 * 0.3);
  std::cout << "closed-loop RMS over gears 7 … 16: " << rms_closed(loop, 6) << " µm, open " << std::sqrt(open_late) << " µm\n";
  // Gear 2's correction cancels exactly what gear 1 showed; the scatter drawn is the same open and closed.
  EXPECT_DOUBLE_EQ(loop[1].correction_um, -loop[0].open_um);
  for (const auto& g : loop) EXPECT_DOUBLE_EQ(g.closed_um - g.open_um, g.correction_um);
}

TEST(ClosedLoop, RefusesWhatItCannotRun) {
  series::ClosedLoopInput in;
  EXPECT_THROW(series::run_closed_loop(in), std::invalid_argument); // no gear
  in.states = every_half_hour(3);
  EXPECT_THROW(series::run_closed_loop(in), std::invalid_argument); // no truth
  in.truth_um = [](const series::GearState&) { return 0.0; };
  in.scatter_um = -1.0;
  EXPECT_THROW(series::run_closed_loop(in), std::invalid_argument);
}
