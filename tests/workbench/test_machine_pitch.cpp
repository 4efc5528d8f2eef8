// geartopo tests — a measuring machine's own pitch table beside geartopo's evaluation of the same traces
// (workbench::compare_machine_pitch), on exports written from the documented structure (trace_export_fixture.hpp)
// with pitch tables computed here from the ISO definitions, not by geartopo's evaluator. Units: mm, µm.
#include "../trace_export_fixture.hpp"

#include "geartopo/measurement/klingelnberg.hpp"
#include "geartopo/workbench/iso_evaluation.hpp"
#include "geartopo/workbench/machine_pitch.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <utility>

using namespace geartopo;
using namespace trace_fixture;

namespace {

constexpr double kPi = std::numbers::pi;

/// An export of every tooth (one profile trace at mid face width, one helix trace at mid profile per flank, constant
/// δn_j per flank) with a pitch table per side written from the ISO definitions (evaluation/pitch.hpp,
/// docs/iso1328.md): the flank's position on the measuring circle d_M (the helix trace's diameter) is the rotation that
/// moves it by δn along its normal, e_j = σ δn_j / (cos β_b cos α_yt) (σ +1 right, −1 left; cos α_yt = d_b/d_M), and
/// f_p,j = e_{j+1} − e_j, F_p,j = e_j − e_1. `table` may alter the written (f_p, F_p) of a row.
struct PitchExport {
  std::string text;
  double d_m_mm = 0.0;
};

PitchExport pitch_export(const std::function<std::pair<double, double>(Flank, int, double fp, double Fp)>& table) {
  const auto& g = ideal_workbench().setup.geometry();
  const int z = g.teeth();
  // A once-per-revolution part, a tooth-to-tooth scatter of ±0.4 µm and a bump at tooth 10.
  const auto dn = [](Flank s, int tooth) {
    return (s == Flank::Left ? 0.8 : -0.6) * std::sin(2 * kPi * tooth / 35.0) + 0.2 * ((tooth * 7) % 5 - 2) + (tooth == 10 ? 0.3 : 0.0);
  };
  Layout l;
  l.teeth.clear();
  for (int t = 1; t <= z; ++t) l.teeth.push_back(t);
  l.profile_z_mm = {0.5 * g.spec().face_width_mm};
  const double xa = g.roll_length_at(g.root_form_diameter_mm()), xe = g.roll_length_at(g.tip_diameter_mm());
  PitchExport out;
  out.d_m_mm = g.diameter_at_roll_length(0.5 * (xa + xe));
  l.helix_d_mm = {out.d_m_mm};
  l.profile_points = l.helix_points = 40;
  out.text = write_export(g, l, [&](Flank s, int tooth, double, double) { return dn(s, tooth); }).text;
  const double cos_bb = std::cos(g.base_helix_angle()), cos_at = g.base_diameter_mm() / out.d_m_mm;
  for (const Flank s : {Flank::Left, Flank::Right}) {
    std::vector<double> e;
    for (int t = 1; t <= z; ++t) e.push_back((s == Flank::Right ? 1.0 : -1.0) * dn(s, t) / (cos_bb * cos_at));
    out.text += s == Flank::Left ? "linke Zahnflanke\nZahn-Nr. fp Fp Fr\n" : "rechte Zahnflanke\nZahn-Nr. fp Fp Fr\n";
    for (int t = 1; t <= z; ++t) {
      const auto j = static_cast<std::size_t>(t - 1);
      const auto [fp, Fp] = table(s, t, e[(j + 1) % e.size()] - e[j], e[j] - e[0]);
      out.text += fmt::format("{} {:.4f} {:.4f} 0.0000\n", t, fp, Fp);
    }
  }
  return out;
}

workbench::MachinePitchComparison beside(const PitchExport& e) {
  const auto& wb = ideal_workbench();
  TempFile f("pitch.mka", e.text);
  const auto file = measurement::read_klingelnberg(f.path.string());
  const auto traces = measurement::klingelnberg_traces(file, wb.setup.geometry());
  const auto iso = workbench::evaluate_iso(wb.setup.geometry(), wb.setup.ranges(), traces);
  return workbench::compare_machine_pitch(file.pitch, iso.evaluation);
}

} // namespace

// The table that evaluates the same traces by the same definitions agrees row by row (the export's 4 decimals).
TEST(MachinePitchTable, AgreesWithGeartoposEvaluationOfTheSameTraces) {
  const auto c = beside(pitch_export([](Flank, int, double fp, double Fp) { return std::make_pair(fp, Fp); }));
  EXPECT_EQ(c.rows.size(), 70u);
  EXPECT_EQ(c.flagged, 0u);
  EXPECT_LT(c.max_abs_fp_difference_um, 1e-3);
  EXPECT_LT(c.max_abs_Fp_difference_um, 1e-3);
  EXPECT_TRUE(c.likely_cause.empty());
}

// A table that numbers pitches by their end tooth is flagged, and the numbering named as the likely cause.
TEST(MachinePitchTable, AnotherNumberingIsFlaggedAndNamed) {
  // f_p of tooth j written as e_j − e_{j−1}: the previous row's f_p (read back through a first pass).
  std::map<std::pair<int, int>, double> fp_of;
  pitch_export([&](Flank s, int t, double fp, double Fp) {
    fp_of[{static_cast<int>(s), t}] = fp;
    return std::make_pair(fp, Fp);
  });
  const auto c = beside(pitch_export([&](Flank s, int t, double, double Fp) {
    return std::make_pair(fp_of[{static_cast<int>(s), t == 1 ? 35 : t - 1}], Fp);
  }));
  EXPECT_GT(c.flagged, 35u); // most of the 70 rows
  EXPECT_GT(c.max_abs_fp_difference_um, 0.1);
  EXPECT_NE(c.likely_cause.find("end tooth"), std::string::npos) << c.likely_cause;
}

// One row off by 0.3 µm: that row (and no other) is flagged; no other convention explains it.
TEST(MachinePitchTable, OneDifferentRowIsFlaggedWithoutAConvention) {
  const auto c = beside(pitch_export([](Flank s, int t, double fp, double Fp) {
    return std::make_pair(fp + (s == Flank::Right && t == 20 ? 0.3 : 0.0), Fp);
  }));
  EXPECT_EQ(c.flagged, 1u);
  for (const auto& r : c.rows) EXPECT_EQ(r.flagged, r.side == Flank::Right && r.tooth == 20);
  EXPECT_NEAR(c.max_abs_fp_difference_um, 0.3, 1e-3);
  EXPECT_NE(c.likely_cause.find("filter"), std::string::npos) << c.likely_cause;
}
