// geartopo — the machine's pitch table beside geartopo's evaluation (machine_pitch.hpp). Units: µm.
#include "geartopo/workbench/machine_pitch.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace geartopo::workbench {
namespace {

const evaluation::PitchEvaluation* side_pitch(const evaluation::GearEvaluation& e, Flank s) {
  const auto& p = s == Flank::Left ? e.pitch_left : e.pitch_right;
  return p ? &*p : nullptr;
}

/// Largest |machine − geartopo| over the rows when geartopo's values are taken as `other` says (tooth j's pitch and
/// index values, or another convention's).
double worst(const std::vector<measurement::KlingelnbergPitchRow>& table, const evaluation::GearEvaluation& e,
             const std::function<double(const evaluation::PitchEvaluation&, std::size_t)>& fp,
             const std::function<double(const evaluation::PitchEvaluation&, std::size_t)>& Fp) {
  double w = 0.0;
  for (const auto& r : table)
    if (const auto* p = side_pitch(e, r.flank); p && r.tooth >= 1 && static_cast<std::size_t>(r.tooth) <= p->position_um.size()) {
      const auto j = static_cast<std::size_t>(r.tooth - 1);
      w = std::max({w, std::abs(r.fp_um - fp(*p, j)), std::abs(r.Fp_um - Fp(*p, j))});
    }
  return w;
}

} // namespace

MachinePitchComparison compare_machine_pitch(const std::vector<measurement::KlingelnbergPitchRow>& table,
                                             const evaluation::GearEvaluation& e) {
  MachinePitchComparison c;
  for (const auto& r : table) {
    const auto* p = side_pitch(e, r.flank);
    if (!p || r.tooth < 1 || static_cast<std::size_t>(r.tooth) > p->position_um.size()) continue;
    const auto j = static_cast<std::size_t>(r.tooth - 1);
    MachinePitchRow row{r.tooth, r.flank, r.fp_um, r.Fp_um, p->single_pitch_um[j], p->index_um[j], false};
    const double dfp = std::abs(row.machine_fp_um - row.geartopo_fp_um), dFp = std::abs(row.machine_Fp_um - row.geartopo_Fp_um);
    c.max_abs_fp_difference_um = std::max(c.max_abs_fp_difference_um, dfp);
    c.max_abs_Fp_difference_um = std::max(c.max_abs_Fp_difference_um, dFp);
    row.flagged = dfp > kMachineMismatchUm || dFp > kMachineMismatchUm;
    c.flagged += row.flagged;
    c.rows.push_back(row);
  }
  if (c.flagged == 0) return c;
  // Which other reading of the table agrees (all rows within the limit): the conventions an export may use [M].
  using P = const evaluation::PitchEvaluation&;
  const auto n = [](P p) { return p.position_um.size(); };
  const auto prev = [&](P p, std::size_t j) { return (j + n(p) - 1) % n(p); };
  struct Reading {
    const char* cause;
    std::function<double(P, std::size_t)> fp, Fp;
  };
  const Reading readings[] = {
      {"the table numbers pitches by their end tooth (f_p of tooth j = e_j − e_{j−1})",
       [&](P p, std::size_t j) { return p.single_pitch_um[prev(p, j)]; }, [](P p, std::size_t j) { return p.index_um[j]; }},
      {"the table has the opposite sign (the other direction of rotation or of the flank's sense)",
       [](P p, std::size_t j) { return -p.single_pitch_um[j]; }, [](P p, std::size_t j) { return -p.index_um[j]; }},
      {"the table numbers pitches by their end tooth and has the opposite sign",
       [&](P p, std::size_t j) { return -p.single_pitch_um[prev(p, j)]; }, [](P p, std::size_t j) { return -p.index_um[j]; }},
      {"F_p is referred to another tooth or to the mean (f_p agrees)",
       [](P p, std::size_t j) { return p.single_pitch_um[j]; }, [&](P p, std::size_t j) {
         // the table's F_p shifted by the mean difference of its side
         double shift = 0.0;
         std::size_t m = 0;
         for (const auto& r : table)
           if (side_pitch(e, r.flank) == &p && r.tooth >= 1 && static_cast<std::size_t>(r.tooth) <= n(p))
             shift += r.Fp_um - p.index_um[static_cast<std::size_t>(r.tooth - 1)], ++m;
         return p.index_um[j] + (m ? shift / static_cast<double>(m) : 0.0);
       }},
  };
  for (const auto& r : readings)
    if (worst(table, e, r.fp, r.Fp) <= kMachineMismatchUm) {
      c.likely_cause = r.cause;
      return c;
    }
  c.likely_cause = "no other numbering or sign explains it: the machine's filter, its measuring diameter or its "
                   "evaluation range differ from geartopo's, or the traces are not what the table evaluated";
  return c;
}

} // namespace geartopo::workbench
