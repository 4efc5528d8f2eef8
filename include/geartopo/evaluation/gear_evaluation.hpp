// geartopo evaluation — one gear: per-flank profile and helix deviations, mean slopes per side, pitch and runout
// (when every tooth was measured), and the ISO 1328-1:2013 flank tolerance classification (docs/iso1328.md).
//
// Units: positions mm, deviations and tolerances µm, angles rad.
#pragma once

#include "geartopo/evaluation/pitch.hpp"
#include "geartopo/core/flank.hpp"
#include "geartopo/evaluation/tolerances.hpp"
#include "geartopo/evaluation/trace.hpp"

#include <optional>
#include <string>
#include <vector>

namespace geartopo::evaluation {

/// The two traces of one flank.
struct FlankMeasurement {
  int tooth = 1; ///< 1..z
  Flank side = Flank::Right;
  Trace profile; ///< positions: roll length ξ (mm), range L_α
  Trace helix;   ///< positions: axial z from the datum face (mm), range L_β
};

/// Normal deviation δn (µm) of one flank at the pitch measuring point (mid face width, diameter d_M).
struct PitchPoint {
  int tooth = 1; ///< 1..z
  Flank side = Flank::Right;
  double normal_deviation_um = 0.0;
};

/// Everything measured on one gear. Any subset of flanks may be given; pitch of a side needs its z flanks, runout
/// needs all 2z.
struct GearMeasurement {
  std::vector<FlankMeasurement> flanks;
  std::vector<PitchPoint> pitch_points;
  std::optional<PitchGeometry> pitch_geometry; ///< required when pitch_points is not empty
  int sector_pitches = 0;                      ///< k for F_pk; 0 = default_sector_pitches(z)
};

struct FlankEvaluation {
  int tooth = 1;
  Flank side = Flank::Right;
  TraceDeviations profile; ///< F_α, f_fα, f_Hα
  TraceDeviations helix;   ///< F_β, f_fβ, f_Hβ
};

/// Mean slopes of one side over its evaluated flanks (nullopt when no flank of that side was evaluated).
struct SideMeans {
  Flank side = Flank::Right;
  int flanks = 0;
  std::optional<double> f_Halpha_m_um; ///< f_Hαm
  std::optional<double> f_Hbeta_m_um;  ///< f_Hβm
};

/// The class of one quantity, judged by its worst (largest |value|) occurrence.
struct QuantityClass {
  Quantity quantity = Quantity::SinglePitch;
  double worst_value_um = 0.0; ///< signed for slopes; compared by absolute value
  std::string where;           ///< e.g. "tooth 3 left", "right flanks", "all spaces"
  std::optional<int> flank_class; ///< 1..11 or kWorseThanClass11; nullopt when classification is refused
};

struct Classification {
  std::optional<std::string> refusal; ///< set when the gear is outside the range of validity: no classes then
  std::vector<QuantityClass> quantities; ///< every evaluated quantity, worst occurrence (also when refused)
  std::optional<int> overall;              ///< worst class of all quantities (nullopt: refused or nothing evaluated)
  std::optional<Quantity> governing;       ///< the quantity that set the overall class (first in the list on a tie)
};

struct GearEvaluation {
  std::vector<FlankEvaluation> flanks; ///< in the order given
  SideMeans left{Flank::Left, 0, std::nullopt, std::nullopt};
  SideMeans right{Flank::Right, 0, std::nullopt, std::nullopt};
  std::optional<PitchEvaluation> pitch_left, pitch_right; ///< nullopt unless all z flanks of that side were measured
  std::optional<RunoutEvaluation> runout;                 ///< nullopt unless all 2z flanks were measured
  std::vector<std::string> notes;                          ///< why something is not available
  Classification classification;
};

/// Evaluates everything measured. z is p.teeth. The deviations are computed even when the gear is outside the range
/// of validity (then classification.refusal says why and no class is given).
/// Throws std::invalid_argument for bad input (tooth outside 1..z, a flank or pitch point given twice, a refused trace
/// — the message names the tooth, side and trace — or pitch points without pitch_geometry).
GearEvaluation evaluate_gear(const GearMeasurement& m, const GearParameters& p);

} // namespace geartopo::evaluation
