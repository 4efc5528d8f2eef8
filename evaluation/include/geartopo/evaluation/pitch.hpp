// geartopo evaluation — pitch deviations (f_p, F_p, F_pk) and runout (F_r) from one measuring point per flank
// (ISO 1328-1:2013 clause 3 and annexes; conventions and derivations in docs/iso1328.md).
//
// Units: normal deviations δn in µm (along the flank normal, plus material positive); flank positions, pitch,
// index and runout values in µm (positions as transverse arc on the measuring circle d_M, +θ sense); angles in rad.
//
// Conventions: teeth are numbered 1..z in the positive angular sense θ; the right flank faces +θ, the left flank −θ;
// plus material moves a right flank +θ and a left flank −θ. Index j − 1 of every vector belongs to tooth j; pitch j
// runs from tooth j to tooth j + 1 (tooth z → tooth 1); tooth space s lies between tooth s and tooth s + 1.
#pragma once

#include "geartopo/core/flank.hpp"

#include <span>
#include <vector>

namespace geartopo::evaluation {

/// Geometry at the measuring point (mid face width, measuring diameter d_M).
struct PitchGeometry {
  double base_helix_angle_rad = 0.0;            ///< β_b (sign irrelevant: only cos β_b is used)
  double transverse_pressure_angle_rad = 0.0;   ///< α_yt at d_M, cos α_yt = d_b / d_M; 0 < α_yt < π/2
  /// η: half the angular transverse space width at d_M, η = π/z − s_yt/d_M (s_yt: transverse arc tooth thickness at
  /// d_M). Runout only: the probe touching both transverse profiles at d_M has its centre where their normals meet,
  /// at the transverse pressure angle α_yt + η. 0 ≤ η < π/2. η = 0 gives the narrow-space approximation
  /// r = −(e_L − e_R)/(2 tan α_yt), which overstates the runout of an eccentric gear by sin(α_yt + η)/sin α_yt
  /// (≈ 9 % for the default scene gear).
  double space_half_angle_rad = 0.0;
};

/// Position deviation of a flank along the measuring circle (transverse arc, +θ sense, µm):
/// e = σ · δn / (cos β_b · cos α_yt), σ = +1 right, −1 left.
double flank_position_um(double normal_deviation_um, Flank side, const PitchGeometry& g);

/// ISO-customary number of pitches of a sector for F_pk (docs/iso1328.md, [M]): k = z/8 rounded half up, at least 2,
/// at most z − 1. Throws std::invalid_argument for z < 3.
int default_sector_pitches(int teeth);

struct PitchEvaluation {
  Flank side = Flank::Right;
  std::vector<double> position_um;     ///< e_j, j = 1..z
  std::vector<double> single_pitch_um; ///< f_p,j = e_{j+1} − e_j (wrapping z → 1)
  std::vector<double> index_um;        ///< F_p,j = e_j − e_1
  double f_p_um = 0.0;                 ///< max_j |f_p,j|
  double F_p_um = 0.0;                 ///< max_j e_j − min_j e_j
  int sector_pitches = 0;              ///< k
  double F_pk_um = 0.0;                ///< max_j |e_{j+k} − e_j| (wrapping)
};

/// Pitch deviations of one flank side from δn of all z flanks (normal_deviation_um[j − 1] for tooth j).
/// k = 0 selects default_sector_pitches(z). Throws std::invalid_argument for z < 3, non-finite values, k outside
/// 1..z − 1, or angles outside their ranges.
PitchEvaluation evaluate_pitch(std::span<const double> normal_deviation_um, Flank side, const PitchGeometry& g,
                               int sector_pitches = 0);

struct RunoutEvaluation {
  std::vector<double> radial_um; ///< r_s, tooth space s = 1..z (ball outwards positive)
  double F_r_um = 0.0;           ///< max_s r_s − min_s r_s
};

/// Runout from δn of all z right and all z left flanks. The probe (ball or pin) in space s touches the right flank of
/// tooth s and the left flank of tooth s + 1 at d_M in the measuring transverse section; its radial displacement
/// (outwards positive; exact to first order for any small flank movement) is
///   r_s = (δn_R,s + δn_L,s+1) / (2 cos β_b sin(α_yt + η))
///       = cos α_yt · (e_R,s − e_L,s+1) / (2 sin(α_yt + η)),
/// which for η = 0 is −(e_L,s+1 − e_R,s) / (2 tan α_yt). An eccentricity δ gives F_r = 2δ. Derivation, and how a
/// sphere in a helical gear differs: docs/iso1328.md.
RunoutEvaluation evaluate_runout(std::span<const double> right_normal_um, std::span<const double> left_normal_um,
                                 const PitchGeometry& g);

} // namespace geartopo::evaluation
