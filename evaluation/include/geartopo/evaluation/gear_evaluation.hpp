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
#include <string_view>
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

/// The direction in which profile and helix deviations are reported (docs/iso1328.md, "Measuring direction").
/// Inputs are always along the flank normal (δn, the topology grid's direction); pitch and runout do not depend on
/// it (F_p, f_p: transverse arc on the measuring circle; F_r: radial).
enum class IsoDirection {
  Transverse, ///< ISO 1328-1 [M]: in the transverse plane, perpendicular to the involute = along the base-circle
              ///< tangent; δt = δn / cos β_b (13 % more than δn for β = 30°). The default.
  Normal,     ///< along the flank normal, δn (what geartopo's topology grid carries; on request)
};

/// The sign rule of the helix slope deviation f_Hβ (docs/iso1328.md, "Signs").
enum class HelixSlopeSign {
  HelixAngle,       ///< ISO 1328-1 / VDI 2612-1 as reported [M]: f_Hβ > 0 when the actual helix angle |β| is larger
                    ///< than designed; f_Hβ = h σ × (rise towards +z), h = +1 right hand (and spur), −1 left hand,
                    ///< σ = +1 right, −1 left flank. Spur gears: f_Hβ > 0 when the actual helix is right-hand. Default.
  RiseTowardsPlusZ, ///< geartopo's earlier rule: f_Hβ > 0 when material increases away from the datum face, every flank
};

/// How deviations are reported. β_b carries the hand: > 0 right hand, < 0 left hand, 0 spur.
struct IsoConventions {
  IsoDirection direction = IsoDirection::Transverse;
  HelixSlopeSign helix_slope_sign = HelixSlopeSign::HelixAngle;
  double base_helix_angle_rad = 0.0; ///< β_b, signed like β; |β_b| < π/2
};

/// "transverse" / "normal"; parse_iso_direction accepts the same words (nullopt otherwise).
std::string_view to_string(IsoDirection d);
std::optional<IsoDirection> parse_iso_direction(std::string_view word);
/// "helix-angle" / "rise-towards-plus-z"; parse_helix_slope_sign accepts the same words.
std::string_view to_string(HelixSlopeSign s);
std::optional<HelixSlopeSign> parse_helix_slope_sign(std::string_view word);
/// One sentence for outputs: the direction and the f_Hα/f_Hβ sign rules in force.
std::string describe(const IsoConventions& c);

/// Factor from a normal deviation to the reported one: 1 (normal) or 1 / cos β_b (transverse).
double reported_per_normal(const IsoConventions& c);
/// Factor turning "rise towards +z" of a helix trace into the reported f_Hβ of a flank of this side: 1, or h σ.
double helix_slope_factor(const IsoConventions& c, Flank side);

/// Everything measured on one gear. Any subset of flanks may be given; pitch of a side needs its z flanks, runout
/// needs all 2z.
struct GearMeasurement {
  std::vector<FlankMeasurement> flanks;
  std::vector<PitchPoint> pitch_points;
  std::optional<PitchGeometry> pitch_geometry; ///< required when pitch_points is not empty
  int sector_pitches = 0;                      ///< k for F_pk; 0 = default_sector_pitches(z)
  IsoConventions conventions;                  ///< how the trace deviations (given along the normal) are reported
};

/// The trace values in the direction of GearEvaluation::conventions (µm). f_Hβ (helix.slope_um) follows the helix
/// sign rule; helix.mean_line_slope_um_per_mm stays the physical slope against z (rise towards +z).
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
  IsoConventions conventions;          ///< the direction and sign rules the values below are in
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
