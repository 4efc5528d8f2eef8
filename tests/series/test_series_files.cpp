// The series library's plain parts: the across-series laws on values written from their own formulas here, the AQDEF
// writer and its strict reader (a round trip, and bad lines refused at file:line), the series file's reader.
// Units: µm, h, s, strokes.
#include "geartopo/aqdef/aqdef.hpp"
#include "geartopo/core/input_error.hpp"
#include "geartopo/core/random.hpp"
#include "geartopo/evaluation/gear_evaluation.hpp"
#include "geartopo/series/aqdef_export.hpp"
#include "geartopo/series/drift_model.hpp"
#include "geartopo/series/series_file.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

using namespace geartopo;

namespace {

/// The message of the InputError `f` throws ("" when it throws none).
template <class F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

} // namespace

// y = 2 + 6 (1 − e^(−t/1.5 h)) + 0.05 µm noise at 10 gears over 6 h: τ and the amplitude within 2σ, the noise-only and
// wear models refused by the F-test, and a gear 40 min later inside the 95 % interval.
TEST(SeriesLaws, ThermalTimeConstantFromItsCurve) {
  random::SplitMix64 rng(11);
  std::vector<series::GearState> s;
  std::vector<double> y;
  const auto truth = [](double t) { return 2.0 + 6.0 * (1.0 - std::exp(-t / 1.5)); };
  for (int k = 0; k < 10; ++k) {
    s.push_back({k * 0.66, 35.0 * k, 0});
    y.push_back(truth(k * 0.66) + 0.05 * rng.normal());
  }
  const auto fit = series::fit_series(s, y, 0.01);
  ASSERT_EQ(fit.chosen.name(), "thermal drift");
  EXPECT_NEAR(fit.chosen.time_constant_h(), 1.5, 2.0 * fit.chosen.parameters[2].sigma);
  EXPECT_NEAR(fit.chosen.parameters[1].value, 6.0, 2.0 * fit.chosen.parameters[1].sigma);
  const auto next = series::predict(fit.chosen, {6.6, 350.0, 0});
  EXPECT_LT(next.lower95_um, truth(6.6));
  EXPECT_GT(next.upper95_um, truth(6.6));
}

// A series much shorter than τ sees a straight line: τ is not determined, and says so.
TEST(SeriesLaws, TimeConstantBeyondTheSeriesIsNotDetermined) {
  std::vector<series::GearState> s;
  std::vector<double> y;
  for (int k = 0; k < 6; ++k) {
    s.push_back({k * 0.1, 0.0, 0});
    y.push_back(1.0 + 10.0 * (1.0 - std::exp(-k * 0.1 / 50.0)) + (k % 2 ? 0.02 : -0.02));
  }
  const auto f = series::fit_laws(s, y, {series::Law::ThermalDrift}, 0.01);
  ASSERT_TRUE(f.has_value());
  EXPECT_FALSE(f->parameters[2].determined) << f->parameters[2].value;
  EXPECT_FALSE(f->parameters[1].determined);
}

// Class loss of a straight wear line y = 0.1 µm/stroke × S, limit 10.5 µm: lost past S = 105 strokes.
TEST(SeriesLaws, ClassLossOfAWearLine) {
  std::vector<series::GearState> s;
  std::vector<double> y;
  for (int k = 0; k < 5; ++k) {
    s.push_back({k * 0.2, 10.0 * k, 0});
    y.push_back(0.1 * 10.0 * k + (k % 2 ? 0.01 : -0.01));
  }
  const auto f = series::fit_laws(s, y, {series::Law::WheelWear}, 0.005);
  ASSERT_TRUE(f.has_value());
  const auto loss = series::class_loss(*f, {1.0, 50.0, 0}, {0.2, 10.0, 0}, 10.5, 100);
  ASSERT_TRUE(loss.gears_median.has_value());
  EXPECT_EQ(*loss.strokes_median, 110.0); // the first gear beyond 100 strokes
  EXPECT_LE(*loss.gears_early, *loss.gears_median);
  EXPECT_GE(loss.gears_late.value_or(1000), *loss.gears_median);
}

TEST(Aqdef, RoundTripKeepsEveryKeyAndValue) {
  aqdef::Part p;
  p.number = "DRW-4711";
  p.description = "helical gear m_n 14 z 35";
  p.machine = "SKMC-1200W/10";
  for (int i = 0; i < 3; ++i) {
    aqdef::Characteristic c;
    c.code = "fHa_T0" + std::to_string(i + 1) + "_L";
    c.description = "f_H_alpha, tooth " + std::to_string(i + 1);
    c.nominal = 0.0;
    c.lower_limit = -7.5;
    c.upper_limit = 7.5;
    c.unit = "um";
    for (int k = 0; k < 4; ++k)
      c.values.push_back({0.1234 * (k + 1) - i, aqdef::format_time(1795759200 + 600 * k), "lot 7",
                          k == 2 ? std::string() : "SN-2026-" + std::to_string(k + 1)});
    p.characteristics.push_back(c);
  }
  p.characteristics[1].lower_limit.reset();
  std::stringstream file;
  aqdef::write_dfq(file, p);
  const std::string text = file.str();
  EXPECT_EQ(text.substr(0, 8), "K0100 3\n");
  EXPECT_NE(text.find("K0004/1 27.11.2026/06:00:00\n"), std::string::npos) << text;
  EXPECT_NE(text.find("K0006/1 lot 7\nK0014/1 SN-2026-1\n"), std::string::npos) << text;
  const aqdef::Part back = aqdef::read_dfq(file, "round.dfq");
  EXPECT_EQ(back.number, p.number);
  EXPECT_EQ(back.description, p.description);
  EXPECT_EQ(back.machine, p.machine);
  ASSERT_EQ(back.characteristics.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const auto &a = p.characteristics[i], &b = back.characteristics[i];
    EXPECT_EQ(b.code, a.code);
    EXPECT_EQ(b.description, a.description);
    EXPECT_EQ(b.lower_limit.has_value(), a.lower_limit.has_value());
    EXPECT_EQ(b.upper_limit, a.upper_limit);
    ASSERT_EQ(b.values.size(), a.values.size());
    for (size_t k = 0; k < a.values.size(); ++k) {
      EXPECT_NEAR(b.values[k].value, a.values[k].value, 0.5e-4); // written with 4 decimals
      EXPECT_EQ(b.values[k].time, a.values[k].time);
      EXPECT_EQ(b.values[k].batch, "lot 7");
      EXPECT_EQ(b.values[k].part_ident, a.values[k].part_ident);
    }
  }
}

TEST(Aqdef, StrictReaderNamesLineAndKey) {
  const auto refused = [](const std::string& text) {
    std::istringstream in(text);
    return input_error_of([&] { aqdef::read_dfq(in, "bad.dfq"); });
  };
  EXPECT_NE(refused("K1001/1 x\n").find("bad.dfq:1:1: K1001: before K0100"), std::string::npos);
  EXPECT_NE(refused("K0100 1\nK2001/1 a\nK0001/1 1,5\n").find("bad.dfq:3:9: K0001: '1,5' is not a finite number"),
            std::string::npos);
  EXPECT_NE(refused("K0100 1\nK2001/2 a\n").find("bad.dfq:2:1: K2001: index 2 outside 1 … 1"), std::string::npos);
  EXPECT_NE(refused("K0100 1\nK2001/1 a\nK2001/1 b\n").find("bad.dfq:3:1: K2001: given twice"), std::string::npos);
  EXPECT_NE(refused("K0100 1\nK2001/1 a\nK0004/1 01.01.2026/00:00:00\n").find("bad.dfq:3:1: K0004: not right after"),
            std::string::npos);
  EXPECT_NE(refused("K0100 1\nK2001/1 a\nK9999/1 x\n").find("bad.dfq:3:1: K9999: not a key"), std::string::npos);
  EXPECT_NE(refused("K0100 2\nK2001/1 a\n").find("K2001/2: characteristic without"), std::string::npos);
  EXPECT_NE(refused("").find("no K0100"), std::string::npos);
  EXPECT_NE(refused("K0100 1\nK2001/1 a\nK0001/1 1\nK0014/1 a\nK0014/1 b\n").find("bad.dfq:5:1: K0014: given twice"),
            std::string::npos);
  EXPECT_NE(refused("K0100 1\nK2001/1 a\nK0014/1 SN1\n").find("bad.dfq:3:1: K0014: not right after"), std::string::npos);
  // K0014 holds 40 characters at most: the writer refuses a longer id rather than have the quality system cut it.
  aqdef::Part p;
  p.characteristics.push_back({"a", "", {}, {}, {}, "", {{1.0, "", "", std::string(41, 'x')}}});
  std::ostringstream out;
  EXPECT_THROW(aqdef::write_dfq(out, p), std::invalid_argument);
}

// ISO values of two gears as characteristics: f_Hα of tooth 1 left carries its two values and ±f_HαT of class 5.
TEST(Aqdef, IsoValuesBecomeCharacteristicsPerToothAndFlank) {
  evaluation::GearEvaluation e1, e2;
  evaluation::FlankEvaluation f;
  f.tooth = 1, f.side = Flank::Left, f.profile.slope_um = 2.5, f.helix.total_um = 4.0;
  e1.flanks.push_back(f);
  f.profile.slope_um = -1.25;
  e2.flanks.push_back(f);
  evaluation::GearParameters p;
  p.teeth = 35, p.reference_diameter_mm = 565.8, p.normal_module_mm = 14.0, p.face_width_mm = 150.0;
  const auto part =
      series::iso_aqdef({{&e1, 1795759200, "SN 1"}, {&e2, std::nullopt, "SN 2"}}, p, 5, {"DRW", "gear", "grinder", "lot"});
  ASSERT_EQ(part.characteristics.size(), 6u);
  const auto& fHa = part.characteristics[2];
  EXPECT_EQ(fHa.code, "fHa_T01_L");
  ASSERT_EQ(fHa.values.size(), 2u);
  EXPECT_EQ(fHa.values[0].value, 2.5);
  EXPECT_EQ(fHa.values[1].value, -1.25);
  EXPECT_EQ(fHa.values[1].time, "");
  EXPECT_EQ(fHa.values[0].part_ident, "SN 1");
  EXPECT_EQ(fHa.values[1].part_ident, "SN 2");
  const double t = evaluation::tolerance_um(evaluation::Quantity::ProfileSlope, p, 5);
  EXPECT_EQ(fHa.upper_limit, t);
  EXPECT_EQ(fHa.lower_limit, -t);
  EXPECT_FALSE(part.characteristics[3].lower_limit.has_value()) << "F_β has no lower limit";
}

TEST(SeriesFile, ReadsTimesDressingAndCorrections) {
  const std::string text = "scene: scene.yaml\nstarted: 2026-11-27T06:00:00\ngears:\n"
                           "  - measurement: g1.csv\n    start_s: 0\n    strokes_since_dressing: 10\n"
                           "  - measurement: g2.csv\n    started: 2026-11-27T06:30:00\n"
                           "  - measurement: g3.csv\n    start_s: 3600\n    dressed_before: true\n"
                           "    corrections: c.csv\n";
  const auto s = series::parse_series(text, "/shop/run/series.yaml", 35.0);
  ASSERT_EQ(s.gears.size(), 3u);
  EXPECT_EQ(s.scene, std::filesystem::path("/shop/run/scene.yaml"));
  EXPECT_EQ(s.gears[1].start_s, 1800.0);
  EXPECT_EQ(s.gears[1].strokes_since_dressing, 45.0);
  EXPECT_EQ(s.gears[2].strokes_since_dressing, 0.0);
  EXPECT_EQ(s.gears[2].corrections, std::filesystem::path("/shop/run/c.csv"));
  EXPECT_EQ(s.gears[1].id, "gear 2");
  EXPECT_EQ(*s.gears[2].start_epoch_s, *series::parse_date_time("2026-11-27 07:00:00"));
  EXPECT_TRUE(s.dressing_known);
}

TEST(SeriesFile, BadEntriesRefusedAtTheirLine) {
  const auto refused = [](const std::string& gears) {
    return input_error_of([&] { series::parse_series("scene: s.yaml\ngears:\n" + gears, "series.yaml", 35.0); });
  };
  EXPECT_NE(refused("  - measurement: a.csv\n    start_s: 10\n  - measurement: b.csv\n    start_s: 5\n")
                .find("series.yaml:6:"), std::string::npos);
  EXPECT_NE(refused("  - measurement: a.csv\n    start_s: 0\n    strokes: 3\n").find("series.yaml:5:"), std::string::npos);
  EXPECT_NE(refused("  - measurement: a.csv\n").find("start_s"), std::string::npos);
  EXPECT_NE(refused("  - measurement: a.csv\n    start_s: -1\n").find("series.yaml:4:"), std::string::npos);
  EXPECT_NE(refused("  - measurement: a.csv\n    started: 2026-11-27T06:00:00\n").find("series' own 'started'"),
            std::string::npos);
  EXPECT_NE(refused("  - measurement: a.csv\n    start_s: 0\n    dressed_before: yes\n").find("series.yaml:5:"),
            std::string::npos);
  EXPECT_NE(refused("  - {measurement: a.csv, start_s: 0, id: x}\n  - {measurement: b.csv, start_s: 1, id: x}\n")
                .find("'x' is listed twice"), std::string::npos);
  EXPECT_NE(input_error_of([] { series::parse_series("scene: s.yaml\n", "series.yaml", 35.0); }).find("gears"),
            std::string::npos);
}

// Issue 41: what the AQDEF export writes from the series file is refused where it is read, at file:line and field,
// when its key cannot hold it: the batch (name → K0006) 14 characters, the machine (K1082) and each gear's id (K0014)
// 40 (diribet/aqdef-tools' KKeyRepository, the Q-DAS database's column widths). Characters, not bytes.
TEST(SeriesFile, TextsLongerThanTheirAqdefKeyRefusedAtTheirLine) {
  const auto read = [](const std::string& head, const std::string& id = "") {
    return series::parse_series(head + "scene: s.yaml\ngears:\n  - measurement: a.csv\n    start_s: 0\n" + id,
                                "series.yaml", 35.0);
  };
  EXPECT_EQ(read("name: shift 27 lot 4\n").name, "shift 27 lot 4") << "14 characters fit";
  EXPECT_EQ(read("name: Los 4711 Größe\n").name, "Los 4711 Größe") << "14 characters in 16 bytes fit";
  EXPECT_EQ(input_error_of([&] { read("name: shift 27, batch 4711\n"); }),
            "series.yaml:1:7: name: 'shift 27, batch 4711' has 20 characters, more than the 14 AQDEF K0006 holds (the "
            "batch, written as AQDEF K0006 by --aqdef)");
  EXPECT_NE(input_error_of([&] { read("machine: " + std::string(41, 'M') + "\n"); })
                .find("series.yaml:1:10: machine: '"), std::string::npos);
  EXPECT_NE(input_error_of([&] { read("", "    id: " + std::string(41, 'G') + "\n"); })
                .find("series.yaml:5:9: gears[0].id: '"), std::string::npos);
  EXPECT_NE(input_error_of([&] { read("", "    id: " + std::string(41, 'G') + "\n"); })
                .find("more than the 40 AQDEF K0014 holds"), std::string::npos);
}

// The writer checks every text and number against its key before anything is written, and the strict reader refuses
// what the writer would not write, at line:column and key.
TEST(Aqdef, EveryWrittenKeyHoldsItsValue) {
  EXPECT_EQ(aqdef::max_characters("K0006"), 14u);
  EXPECT_EQ(aqdef::max_characters("K2001"), 20u);
  const auto written = [](const aqdef::Part& p) {
    std::ostringstream out;
    try {
      aqdef::write_dfq(out, p);
    } catch (const std::invalid_argument& e) {
      EXPECT_TRUE(out.str().empty()) << "written before refused";
      return std::string(e.what());
    }
    return std::string("(written)");
  };
  aqdef::Part p;
  p.characteristics.push_back({"fHa_T01_L", "", 0.0, {}, {}, "um", {{1.0, "", "lot 4711", "G001"}}});
  EXPECT_EQ(written(p), "(written)");
  p.characteristics[0].values[0].batch = "shift 27, lot 4711"; // 18
  EXPECT_EQ(written(p), "AQDEF K0006: 'shift 27, lot 4711' has 18 characters, more than the 14 AQDEF K0006 holds");
  p.characteristics[0].values[0].batch = "lot 4711";
  p.characteristics[0].code = "fHa_T01_L_profile_slope"; // 23
  EXPECT_NE(written(p).find("AQDEF K2001: 'fHa_T01_L_profile_slope' has 23 characters, more than the 20"), std::string::npos);
  p.characteristics[0].code = "fHa_T01_L";
  p.number = std::string(31, 'D');
  EXPECT_NE(written(p).find("AQDEF K1001:"), std::string::npos);
  p.number = "DRW-4711";
  p.characteristics[0].values[0].value = 1e30; // 35 characters with 4 decimals
  EXPECT_NE(written(p).find("AQDEF K0001: "), std::string::npos);
  EXPECT_NE(written(p).find("more than the 22 a number holds"), std::string::npos);
  std::istringstream in("K0100 1\nK2001/1 a\nK0001/1 1\nK0006/1 shift 27, lot 4711\n");
  EXPECT_EQ(input_error_of([&] { aqdef::read_dfq(in, "bad.dfq"); }),
            "bad.dfq:4:9: K0006: 'shift 27, lot 4711' has 18 characters, more than the 14 AQDEF K0006 holds");
}

// Pitch per gear: flank positions on the measuring circle e_j = A sin(2π (j − 1)/z + 0.3), the same on both sides (a
// gear whose teeth are displaced once round, like a wobbling index), given to the evaluator as the normal deviations
// δn = ±e cos β_b cos α_yt (pitch.hpp). F_p is the spread of the positions, f_p the largest step between neighbours;
// for a sinusoid F_p ≈ 2A and f_p ≈ 2A sin(π/z). Each gear adds one value with its id (K0014) to f_p and F_p of each
// side and to F_r, each limited by the class's tolerance, and all of it survives the strict reader.
TEST(Aqdef, PitchAndRunoutPerGearWithTheGearsId) {
  constexpr int z = 35;
  evaluation::PitchGeometry g;
  g.base_helix_angle_rad = 0.3, g.transverse_pressure_angle_rad = 0.38, g.space_half_angle_rad = 0.05;
  const double to_normal = std::cos(g.base_helix_angle_rad) * std::cos(g.transverse_pressure_angle_rad);
  const auto gear = [&](double a_um) {
    evaluation::GearEvaluation e;
    std::vector<double> right, left;
    for (int j = 0; j < z; ++j) {
      const double pos = a_um * std::sin(2.0 * std::numbers::pi * j / z + 0.3);
      right.push_back(pos * to_normal), left.push_back(-pos * to_normal);
    }
    e.pitch_left = evaluation::evaluate_pitch(left, Flank::Left, g);
    e.pitch_right = evaluation::evaluate_pitch(right, Flank::Right, g);
    e.runout = evaluation::evaluate_runout(right, left, g);
    return e;
  };
  const auto truth = [&](double a_um) {
    double lo = 1e9, hi = -1e9, step = 0.0;
    for (int j = 0; j < z; ++j) {
      const double p = a_um * std::sin(2.0 * std::numbers::pi * j / z + 0.3);
      const double next = a_um * std::sin(2.0 * std::numbers::pi * (j + 1) / z + 0.3);
      lo = std::min(lo, p), hi = std::max(hi, p), step = std::max(step, std::abs(next - p));
    }
    return std::pair{step, hi - lo};
  };
  const evaluation::GearEvaluation e1 = gear(6.0), e2 = gear(8.0);
  evaluation::GearParameters p;
  p.teeth = z, p.reference_diameter_mm = 565.8, p.normal_module_mm = 14.0, p.face_width_mm = 150.0;
  const auto part = series::iso_aqdef({{&e1, 1795759200, "SN-0001"}, {&e2, 1795762800, "SN-0002"}}, p, 6,
                                      {"DRW", "gear", "grinder", "lot"});
  ASSERT_EQ(part.characteristics.size(), 5u); // no flank traces: pitch and runout only
  std::stringstream file;
  aqdef::write_dfq(file, part);
  const auto back = aqdef::read_dfq(file, "pitch.dfq");
  const std::vector<std::string> codes{"fp_L", "Fp_L", "fp_R", "Fp_R", "Fr"};
  for (size_t i = 0; i < codes.size(); ++i) {
    const auto& c = back.characteristics[i];
    EXPECT_EQ(c.code, codes[i]);
    ASSERT_EQ(c.values.size(), 2u) << codes[i];
    EXPECT_EQ(c.values[0].part_ident, "SN-0001");
    EXPECT_EQ(c.values[1].part_ident, "SN-0002");
    EXPECT_EQ(c.values[1].time, "27.11.2026/07:00:00");
    EXPECT_FALSE(c.lower_limit.has_value()) << codes[i];
    const auto q = i == 4 ? evaluation::Quantity::Runout
                          : i % 2 == 0 ? evaluation::Quantity::SinglePitch : evaluation::Quantity::CumulativePitch;
    EXPECT_NEAR(*c.upper_limit, evaluation::tolerance_um(q, p, 6), 0.5e-4) << codes[i];
    if (i == 4) {
      EXPECT_NEAR(c.values[0].value, e1.runout->F_r_um, 0.5e-4);
      continue;
    }
    for (int k = 0; k < 2; ++k) {
      const double a = k == 0 ? 6.0 : 8.0;
      const auto [f_p, F_p] = truth(a);
      EXPECT_NEAR(c.values[k].value, i % 2 == 0 ? f_p : F_p, 1e-4) << codes[i] << " gear " << k + 1;
      EXPECT_LE(c.values[k].value, i % 2 == 0 ? 2 * a * std::sin(std::numbers::pi / z) + 1e-4 : 2 * a + 1e-4);
      EXPECT_GE(c.values[k].value, i % 2 == 0 ? 0.95 * 2 * a * std::sin(std::numbers::pi / z) : 2 * a * std::cos(std::numbers::pi / z));
    }
  }
}
